/* Chaos indicators for R orbits at once: the splitting schemes' drift/kick steps, the models'
 * forces and tangent forces, and the mLE/SALI/GALI bookkeeping of chaos.c, written over lanes
 * (orbits) innermost. The arithmetic of every lane is that of models.c, splitting.c and chaos.c
 * expression for expression (same operations in the same order, no reassociation), so a lane
 * reproduces the single-orbit run to the last bit when both are compiled alike.
 *
 * Layout: slots (lanes) in groups of LANES (one AVX2 vector of doubles), each group's block
 * contiguous: y[(g rows + (2m + c) N + j) LANES + w] is component c (0 = x, 1 = p) of particle j
 * of vector m (0 = the orbit, 1..n_dev the deviation vectors) in slot s = g LANES + w, rows =
 * 2N(1 + n_dev): element [j][r] with r contiguous within the group. A group runs a whole
 * renormalisation interval while its few kB of state stay in L1, with the loops over its LANES
 * slots compiled to single vector instructions. Running lanes are kept in the
 * first slots (compaction), so finished lanes cost nothing. */
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <gsl/gsl_randist.h>
#include <gsl/gsl_rng.h>
#include "fputlab/chaos_batch.h"
#include "internal.h"
#include "model_terms.h"
#include "chaos_terms.h"

#define LANES 4
#define MSG_LEN 192
#define FPL_INLINE static inline __attribute__((always_inline))

enum { N_LANE_ACC = 21, N_HEADER = 8 };
#define SAVE_MAGIC 20261123.0

struct fpl_chaos_batch {
    int R, n, k, model, S;
    int ring;                /* periodic boundary: bond 0 joins particle N-1 and 0 */
    long rows;               /* 2N(1 + n_dev) rows of the state */
    double alpha, beta, dt, t0, T, t_first, tau;
    double stretch_limit;    /* blow-up check at each renormalisation (0: none) */
    long n_renorm, n_steps, m;
    const fpl_splitting *scheme;
    const fpl_lattice **lat;
    fpl_chaos_options opt;   /* the per-lane options (fpl_chaos_batch_options.chaos) */
    int compact;
    fpl_event_set ev;        /* the criteria of integrator_options->events */
    char ev_desc[8][96];
    fpl_work *work;          /* lone lanes (run_lone) and the criteria of initial states */
    int n_active;            /* running lanes */
    int *orbit_of_slot;      /* S entries, -1 for an empty slot */
    int *slot_of_orbit;      /* R entries, -1 once finished (compact mode) */
    double *y, *backup, *part, *q;
    double *cl, *cn, *sc, *minv;   /* N x S coefficients (model 2: cl = cn = sc = v, minv = 1/v;
                                      model 3: cn = v) */
    double *phi, *kap, *dphi;      /* (N+1) x LANES scratch of the kick */
    double *nrm, *inv, *acc1, *acc2, *gali, *fin;  /* per-slot renormalisation scratch */
    unsigned char *fired;          /* per slot: a criterion fired (or non-finite) in this interval */
    unsigned char *vacated;        /* per slot: emptied by compaction, to be cleared */
    long *fired_step;              /* step (from the interval start) of the check that saw it */
    double *lane_y;                /* 2N(1+k): one lane, AoS */
    double *final_y;               /* R x 2N(1+k): state of each finished lane */
    int *groups, *vgroups;
    /* per orbit */
    double *logsum;
    double *megno_acc;    /* R x 3: MEGNO's integrals per orbit (fpl_megno_step) */
    int *next, *pending;
    fpl_chaos_batch_result *res;
    char (*msg)[MSG_LEN];
};

void fpl_chaos_batch_options_init(fpl_chaos_batch_options *opt)
{
    if (!opt) return;
    memset(opt, 0, sizeof *opt);
    fpl_chaos_options_init(&opt->chaos);  /* one set of defaults for both chaos handles */
    opt->compact = 1;
}

/* The batch kernel runs the splitting schemes with the kinetic drift (no run_setup of their
 * own), in the registry's order: the one list of batch methods (Python reads it from here). */
int fpl_chaos_batch_method_count(void)
{
    int count = 0;
    for (int i = 0; i < fpl_splitting_count(); i++) count += !fpl_splitting_at(i)->run_setup;
    return count;
}

const char *fpl_chaos_batch_method_name(int index)
{
    for (int i = 0; i < fpl_splitting_count(); i++) {
        const fpl_splitting *sch = fpl_splitting_at(i);
        if (!sch->run_setup && index-- == 0) return sch->name;
    }
    return NULL;
}

/* ---- the step over one group of LANES slots ---------------------------------------------- */

/* A group's LANES doubles as one value: GCC's generic vectors (one AVX2 register in the
 * x86-64-v3 clone, two SSE2 registers in the baseline one). Element-wise IEEE operations, so
 * each lane computes exactly what the scalar code computes. Rows are 32-byte aligned. */
typedef double vd __attribute__((vector_size(LANES * sizeof(double))));
#define V(ptr) (*(vd *)(void *)(ptr))
#define VC(ptr) (*(const vd *)(const void *)(ptr))

/* Row r of a group's block (each group's LANES slots are contiguous: [group][row][lane]). */
#define ROW(base, r) ((base) + (size_t)(r) * LANES)

/* The group's blocks of the state y and of the coefficients. */
typedef struct grp {
    double *y;
    const double *cl, *cn, *sc, *minv;
} grp;

FPL_INLINE grp group_at(const fpl_chaos_batch *B, double *y, int g)
{
    const size_t cb = (size_t)g * B->n * LANES;
    grp G = {y + (size_t)g * B->rows * LANES, B->cl + cb, B->cn + cb, B->sc + cb, B->minv + cb};
    return G;
}

/* x^(m) += h minv p^(m) for the orbit and every deviation vector (splitting.c: drift). */
FPL_INLINE void drift_group(const fpl_chaos_batch *B, grp G, double h, int model, int k)
{
    const int n = B->n;
    for (int m = 0; m <= k; m++) {
        double *xm = G.y + (size_t)2 * n * m * LANES, *pm = xm + (size_t)n * LANES;
        for (int i = 0; i < n; i++) {
            /* minv = 1 except for model 2: h * 1 * p = h * p exactly */
            if (model == FPL_MODEL_HAMILTONIAN) FPL_DRIFT(V(ROW(xm, i)), h, VC(ROW(G.minv, i)), VC(ROW(pm, i)));
            else FPL_DRIFT_UNIT(V(ROW(xm, i)), h, VC(ROW(pm, i)));
        }
    }
}

/* Bond b's force phi_b and curvature kap_b for the group (models.c: bond_forces_homogeneous /
 * bond_forces_generic; model 3 is the generic form with cl = s = 1, whose multiplications by 1
 * are exact and left out). which: 0 the left end (b = 0), 1 interior (b = j), 2 the right end
 * (b = N, j = N). */
FPL_INLINE void bond(const fpl_chaos_batch *B, grp G, int j, int which, int model, vd *phi, vd *kap)
{
    const double a = B->alpha, b = B->beta;
    /* a ring's bond 0 (which = 0) joins particle N-1 and 0: the interior form with j - 1 = N-1
     * (its bond N is bond 0, never formed here) */
    const int wrap = which == 0 && B->ring;
    const int jc = which == 2 ? j - 1 : j, lc = wrap ? B->n - 1 : which == 0 ? j : j - 1;
    const vd xj = VC(ROW(G.y, jc)), xl = VC(ROW(G.y, lc));
    if (model == FPL_MODEL_HOMOGENEOUS) {
        const vd d = wrap ? xj - xl : which == 0 ? xj : which == 1 ? xj - xl : -xl;
        *phi = FPL_HOM_PHI(d, a, b);
        *kap = FPL_HOM_KAPPA(d, a, b);
        return;
    }
    if (model == FPL_MODEL_TODA) {
        /* model_toda.c: toda_bonds (fpl_expm1's four-lane form: the same bits per lane) */
        const double two_a = 2.0 * a, inv_2a = 0.5 / a;
        const vd d = wrap ? xj - xl : which == 0 ? xj : which == 1 ? xj - xl : -xl;
        vd m;
        FPL_TODA_M_V4(m, d, two_a);
        *phi = FPL_TODA_PHI(m, inv_2a);
        *kap = FPL_TODA_KAPPA(m);
        return;
    }
    const int plain = model == FPL_MODEL_NONLINEAR;
    const vd cnj = VC(ROW(G.cn, jc)), cnl = VC(ROW(G.cn, lc));
    vd L, R;
    if (wrap) {
        /* models_periodic.c: bond_forces_periodic */
        L = plain ? xj - xl : VC(ROW(G.cl, jc)) * xj - VC(ROW(G.cl, lc)) * xl;
        R = cnj * xj - cnl * xl;
    } else if (which == 0) {
        L = plain ? xj : VC(ROW(G.cl, jc)) * xj;
        R = cnj * xj;
    } else if (which == 1) {
        L = plain ? xj - xl : VC(ROW(G.cl, jc)) * xj - VC(ROW(G.cl, lc)) * xl;
        R = cnj * xj - cnl * xl;
    } else {
        L = plain ? -xl : -VC(ROW(G.cl, lc)) * xl;
        R = -cnl * xl;
    }
    *phi = FPL_PHI(L, R, a, b);
    *kap = FPL_KAPPA(R, a, b);
}

/* Tangent bond force dphi_b of one deviation vector (rows dx) (models.c: bond_tangent_*). */
FPL_INLINE void bond_tangent(const fpl_chaos_batch *B, grp G, const double *dx, int j, int which,
                             int model, const vd *kp, vd *out)
{
    const vd kap = *kp;
    const int wrap = which == 0 && B->ring;
    const int jc = which == 2 ? j - 1 : j, lc = wrap ? B->n - 1 : which == 0 ? j : j - 1;
    const vd dj = VC(ROW(dx, jc)), dl = VC(ROW(dx, lc));
    if (model == FPL_MODEL_HOMOGENEOUS || model == FPL_MODEL_TODA) {
        /* the Toda tangent as model 1's (model_toda.c: toda_bond_tangent; kap * -dl == -kap * dl) */
        *out = wrap || which == 1 ? kap * (dj - dl) : which == 0 ? kap * dj : -kap * dl;
        return;
    }
    const int plain = model == FPL_MODEL_NONLINEAR;
    const vd cnj = VC(ROW(G.cn, jc)), cnl = VC(ROW(G.cn, lc));
    if (wrap)
        *out = FPL_DPHI(plain ? dj - dl : VC(ROW(G.cl, jc)) * dj - VC(ROW(G.cl, lc)) * dl, kap,
                        cnj * dj - cnl * dl);
    else if (which == 0)
        *out = FPL_DPHI_LEFT(plain ? dj : VC(ROW(G.cl, jc)) * dj, kap, cnj, dj);
    else if (which == 1)
        *out = FPL_DPHI(plain ? dj - dl : VC(ROW(G.cl, jc)) * dj - VC(ROW(G.cl, lc)) * dl, kap,
                        cnj * dj - cnl * dl);
    else
        *out = FPL_DPHI_RIGHT(plain ? -dl : -VC(ROW(G.cl, lc)) * dl, kap, cnl, dl);
}

/* p_i += h s_i (phi_{i+1} - phi_i) (models.c: add_divergence; s = 1 except for model 2). */
FPL_INLINE void divergence(grp G, double *p, int i, double h, int model, const vd *f1,
                           const vd *f0)
{
    if (model == FPL_MODEL_HAMILTONIAN) FPL_KICK(V(ROW(p, i)), h, VC(ROW(G.sc, i)), *f1, *f0);
    else FPL_KICK_UNIT(V(ROW(p, i)), h, *f1, *f0);
}

/* Bond j (which = 1 interior, 2 the right end with j = N) completes particle j-1's kick; then
 * particle j-1 is drifted (all vectors). */
FPL_INLINE void kick_drift_particle(const fpl_chaos_batch *B, grp G, int j, int which, double h,
                                    double hd, int model, int k, vd *fprev, vd *dprev,
                                    const vd *fwrap, const vd *dwrap)
{
    const int n = B->n;
    double *y = G.y, *p = y + (size_t)n * LANES;
    /* a ring's bond N is its bond 0, formed before particle 0 was drifted: its stored values
     * (fwrap, dwrap; models_periodic.c sets phi_N = phi_0 likewise) */
    const int wrap = which == 2 && B->ring;
    vd f, kap = {0};   /* not read on the wrap-around bond */
    if (wrap) f = *fwrap;
    else bond(B, G, j, which, model, &f, &kap);
    divergence(G, p, j - 1, h, model, &f, fprev);
    *fprev = f;
    for (int m = 1; m <= k; m++) {
        double *dx = y + (size_t)2 * n * m * LANES;
        vd df;
        if (wrap) df = dwrap[m - 1];
        else bond_tangent(B, G, dx, j, which, model, &kap, &df);
        divergence(G, dx + (size_t)n * LANES, j - 1, h, model, &df, &dprev[m - 1]);
        dprev[m - 1] = df;
    }
    for (int m = 0; m <= k; m++) {
        double *x = ROW(y + (size_t)2 * n * m * LANES, j - 1);
        const double *pm = ROW(y + (size_t)(2 * m + 1) * n * LANES, j - 1);
        if (model == FPL_MODEL_HAMILTONIAN) FPL_DRIFT(V(x), hd, VC(ROW(G.minv, j - 1)), VC(pm));
        else FPL_DRIFT_UNIT(V(x), hd, VC(pm));
    }
}

/* The kick p += h F(x), dp^(m) += h J(x) dx^(m), fused with the drift that follows it
 * (x^(m) += hd minv p^(m)): one pass over the particles, the previous bond's forces carried
 * along, and particle i drifted as soon as its kick is complete (bond i+1 done). Every element
 * gets exactly the operations of kick-then-drift, in the same order. Any k; for few vectors
 * kick_drift_carried below does the same with its values in registers. */
FPL_INLINE void kick_drift_any(const fpl_chaos_batch *B, grp G, double h, double hd, int model,
                               int k)
{
    const int n = B->n;
    vd *dprev = (vd *)(void *)B->dphi; /* k: dphi of the previous bond, per deviation vector */
    vd *dwrap = dprev + k;             /* k: a ring's dphi of bond 0 (= bond N) */
    vd fprev, kap, fwrap;
    bond(B, G, 0, 0, model, &fprev, &kap);
    fwrap = fprev;
    for (int m = 1; m <= k; m++) {
        bond_tangent(B, G, G.y + (size_t)2 * n * m * LANES, 0, 0, model, &kap, &dprev[m - 1]);
        dwrap[m - 1] = dprev[m - 1];
    }
    for (int j = 1; j < n; j++)
        kick_drift_particle(B, G, j, 1, h, hd, model, k, &fprev, dprev, &fwrap, dwrap);
    kick_drift_particle(B, G, n, 2, h, hd, model, k, &fprev, dprev, &fwrap, dwrap);
}

/* The vectors kick_drift_carried keeps in registers (the mLE + SALI runs have 2). */
#define CARRIED_VECTORS 2

/* kick_drift_any for k <= CARRIED_VECTORS, the same operations on the same values in a
 * cheaper order: a bond's left particle was the previous bond's right one, so its coordinates
 * and their products with cl and cn are carried from the previous bond instead of loaded and
 * multiplied again (the same doubles: the particle is drifted only after both of its bonds);
 * a kicked momentum feeds the drift from its register; alpha and beta are locals, which a
 * store through a double * cannot change (B->alpha could). Loads and multiplications per
 * particle and vector: 3 and 2 instead of 6 and 4 for model 3. */
FPL_INLINE void kick_drift_carried(const fpl_chaos_batch *B, grp G, double h, double hd,
                                   int model, int k)
{
    const int n = B->n;
    const double a = B->alpha, b = B->beta, two_a = 2.0 * a, inv_2a = 0.5 / a;
    const int cl_rows = model == FPL_MODEL_HAMILTONIAN, cn_rows = cl_rows || model == FPL_MODEL_NONLINEAR;
    const size_t stride = (size_t)2 * n * LANES; /* from one vector's block to the next */
    vd dprev[CARRIED_VECTORS], dwrap[CARRIED_VECTORS], fprev, kap, fwrap;
    /* per vector m (0: the orbit): x_{j-1}, cl_{j-1} x_{j-1}, cn_{j-1} x_{j-1} */
    vd xc[CARRIED_VECTORS + 1], lc[CARRIED_VECTORS + 1], rc[CARRIED_VECTORS + 1];
    bond(B, G, 0, 0, model, &fprev, &kap);
    fwrap = fprev;
    for (int m = 1; m <= k; m++) {
        bond_tangent(B, G, G.y + stride * m, 0, 0, model, &kap, &dprev[m - 1]);
        dwrap[m - 1] = dprev[m - 1];
    }
    for (int m = 0; m <= k; m++) {
        xc[m] = VC(G.y + stride * m);
        lc[m] = cl_rows ? VC(G.cl) * xc[m] : xc[m];
        rc[m] = cn_rows ? VC(G.cn) * xc[m] : xc[m];
    }
    for (int j = 1; j < n; j++) {
        const vd clj = cl_rows ? VC(ROW(G.cl, j)) : (vd){0}, cnj = cn_rows ? VC(ROW(G.cn, j)) : (vd){0};
        vd pn[CARRIED_VECTORS + 1];
        /* the orbit's bond j: bond() with which = 1 */
        {
            const vd xj = VC(ROW(G.y, j));
            vd f;
            if (model == FPL_MODEL_HOMOGENEOUS) {
                const vd d = xj - xc[0];
                f = FPL_HOM_PHI(d, a, b);
                kap = FPL_HOM_KAPPA(d, a, b);
            } else if (model == FPL_MODEL_TODA) {
                const vd d = xj - xc[0];
                vd mm;
                FPL_TODA_M_V4(mm, d, two_a);
                f = FPL_TODA_PHI(mm, inv_2a);
                kap = FPL_TODA_KAPPA(mm);
            } else {
                const vd lx = cl_rows ? clj * xj : xj, rx = cnj * xj;
                const vd L = lx - lc[0], R = rx - rc[0];
                f = FPL_PHI(L, R, a, b);
                kap = FPL_KAPPA(R, a, b);
                lc[0] = lx;
                rc[0] = rx;
            }
            xc[0] = xj;
            double *p = ROW(G.y + (size_t)n * LANES, j - 1);
            vd pv = VC(p);
            if (model == FPL_MODEL_HAMILTONIAN) FPL_KICK(pv, h, VC(ROW(G.sc, j - 1)), f, fprev);
            else FPL_KICK_UNIT(pv, h, f, fprev);
            V(p) = pv;
            pn[0] = pv;
            fprev = f;
        }
        /* the vectors' tangent bond j: bond_tangent() with which = 1 */
        for (int m = 1; m <= k; m++) {
            const double *dx = G.y + stride * m;
            const vd dj = VC(ROW(dx, j));
            vd df;
            if (model == FPL_MODEL_HOMOGENEOUS || model == FPL_MODEL_TODA) {
                df = kap * (dj - xc[m]);
            } else {
                const vd lx = cl_rows ? clj * dj : dj, rx = cnj * dj;
                df = FPL_DPHI(lx - lc[m], kap, rx - rc[m]);
                lc[m] = lx;
                rc[m] = rx;
            }
            xc[m] = dj;
            double *p = ROW(G.y + stride * m + (size_t)n * LANES, j - 1);
            vd pv = VC(p);
            if (model == FPL_MODEL_HAMILTONIAN) FPL_KICK(pv, h, VC(ROW(G.sc, j - 1)), df, dprev[m - 1]);
            else FPL_KICK_UNIT(pv, h, df, dprev[m - 1]);
            V(p) = pv;
            pn[m] = pv;
            dprev[m - 1] = df;
        }
        /* particle j-1's kick is complete: its drift */
        for (int m = 0; m <= k; m++) {
            double *x = ROW(G.y + stride * m, j - 1);
            if (model == FPL_MODEL_HAMILTONIAN) FPL_DRIFT(V(x), hd, VC(ROW(G.minv, j - 1)), pn[m]);
            else FPL_DRIFT_UNIT(V(x), hd, pn[m]);
        }
    }
    kick_drift_particle(B, G, n, 2, h, hd, model, k, &fprev, dprev, &fwrap, dwrap);
}

FPL_INLINE void kick_drift_group(const fpl_chaos_batch *B, grp G, double h, double hd, int model,
                                 int k)
{
    if (k <= CARRIED_VECTORS) kick_drift_carried(B, G, h, hd, model, k);
    else kick_drift_any(B, G, h, hd, model, k);
}

/* One step of the scheme (splitting.c: fpl_split_step on the lattice's kinetic split) for one
 * group. */
FPL_INLINE void step_group(const fpl_chaos_batch *B, grp G, double dt, int model, int k)
{
    const fpl_splitting *sch = B->scheme;
    const int s = sch->n_kicks;
    drift_group(B, G, sch->drift[0] * dt, model, k);
    for (int i = 0; i < s; i++)
        kick_drift_group(B, G, sch->kick[i] * dt, sch->drift[i + 1] * dt, model, k);
}

/* Criteria of the group's orbits (events.c: fpl_events_eval): fired[s] |= some criterion has
 * value >= threshold, or the value is not finite. */
FPL_INLINE void check_group(const fpl_chaos_batch *B, grp G, unsigned char *fired)
{
    const int n = B->n;
    const size_t S = LANES;
    const double *y = G.y;
    const fpl_event_set *ev = &B->ev;
    int bad[LANES] = {0};
    for (int c = 0; c < ev->n; c++) {
        double v[LANES];
        const double thr = ev->threshold[c];
        if (ev->kind[c] == FPL_EVENT_MAX_STRETCH) {
            const double *restrict x0 = ROW(y, 0), *restrict xl = ROW(y, n - 1);
            for (int w = 0; w < LANES; w++) v[w] = fmax(fabs(x0[w]), fabs(xl[w]));
            for (int j = 1; j < n; j++) {
                const double *restrict xj = ROW(y, j), *restrict xm = ROW(y, j - 1);
                for (int w = 0; w < LANES; w++) v[w] = fmax(v[w], fabs(xj[w] - xm[w]));
            }
        } else if (ev->kind[c] == FPL_EVENT_MAX_DISPLACEMENT) {
            for (int w = 0; w < LANES; w++) v[w] = 0.0;
            for (int j = 0; j < n; j++) {
                const double *restrict xj = ROW(y, j);
                for (int w = 0; w < LANES; w++) v[w] = fmax(v[w], fabs(xj[w]));
            }
        } else { /* FPL_EVENT_ENERGY (models.c: energy_with, c = cn for models 1-2, cl for 3) */
            const double a = B->alpha, b = B->beta;
            const double *p = y + (size_t)n * S;
            const double *c = B->model == FPL_MODEL_HAMILTONIAN ? G.cn : G.cl;
            for (int w = 0; w < LANES; w++) v[w] = 0.0;
            for (int i = 0; i < n; i++) {
                const double *restrict pi = ROW(p, i), *restrict mi = ROW(G.minv, i);
                for (int w = 0; w < LANES; w++) v[w] += 0.5 * mi[w] * pi[w] * pi[w];
            }
            for (int j = 0; j <= n; j++) {
                for (int w = 0; w < LANES; w++) {
                    double r = (j < n ? ROW(c, j)[w] * ROW(y, j)[w] : 0.0)
                             - (j > 0 ? ROW(c, j - 1)[w] * ROW(y, j - 1)[w] : 0.0);
                    v[w] += FPL_BOND_ENERGY(r, a, b);
                }
            }
        }
        /* NaN/Inf counts as fired, as in events.c */
        for (int w = 0; w < LANES; w++) bad[w] |= !(v[w] < thr);
    }
    for (int w = 0; w < LANES; w++) fired[w] |= (unsigned char)bad[w];
}

/* The criteria of a ring or the Toda lattice, lane by lane through events.c on a copy of each
 * running lane's orbit (the polynomial fixed-end forms of check_group are not theirs): the
 * single-orbit numbers, at O(N) per lane every FPL_EVENT_BLOCK steps. */
static void check_group_any(fpl_chaos_batch *B, grp G, int g, unsigned char *fired)
{
    const int n = B->n;
    for (int w = 0; w < LANES; w++) {
        const int o = B->orbit_of_slot[g * LANES + w];
        if (o < 0) continue;
        double *ly = B->lane_y, v[8];
        for (int r = 0; r < 2 * n; r++) ly[r] = ROW(G.y, r)[w];
        fpl_events_eval(B->lat[o], B->work, &B->ev, ly, v);
        for (int c = 0; c < B->ev.n; c++) fired[w] |= (unsigned char)!(v[c] > 0.0);
    }
}

/* Advance one group by nsteps steps of dt; with criteria, check them every FPL_EVENT_BLOCK steps
 * (the lane's block boundaries are those of fpl_integrator_advance from the interval start). */
FPL_INLINE void run_group(fpl_chaos_batch *B, double *y, int g, long nsteps, double dt, int model,
                          int k, int check)
{
    const grp G = group_at(B, y, g);
    const int s0 = g * LANES;
    if (B->ev.n == 0 || !check) {
        for (long i = 0; i < nsteps; i++) step_group(B, G, dt, model, k);
        return;
    }
    for (long done = 0; done < nsteps;) {
        long block = nsteps - done < FPL_EVENT_BLOCK ? nsteps - done : FPL_EVENT_BLOCK;
        for (long i = 0; i < block; i++) step_group(B, G, dt, model, k);
        done += block;
        unsigned char before[LANES];
        memcpy(before, B->fired + s0, LANES);
        if (B->ring || model == FPL_MODEL_TODA) check_group_any(B, G, g, B->fired + s0);
        else check_group(B, G, B->fired + s0);
        for (int w = 0; w < LANES; w++)
            if (B->fired[s0 + w] && !before[w]) B->fired_step[s0 + w] = done;
    }
}

FPL_HOT static void run_groups_homogeneous(fpl_chaos_batch *B, double *y, const int *gl, int ng,
                                            long nsteps, double dt, int check)
{
    /* two deviation vectors (mLE + SALI), the usual case, get a build of their own */
    if (B->k == 2)
        for (int g = 0; g < ng; g++) run_group(B, y, gl[g], nsteps, dt, FPL_MODEL_HOMOGENEOUS, 2, check);
    else
        for (int g = 0; g < ng; g++) run_group(B, y, gl[g], nsteps, dt, FPL_MODEL_HOMOGENEOUS, B->k, check);
}

FPL_HOT static void run_groups_hamiltonian(fpl_chaos_batch *B, double *y, const int *gl, int ng,
                                            long nsteps, double dt, int check)
{
    /* two deviation vectors (mLE + SALI), the usual case, get a build of their own */
    if (B->k == 2)
        for (int g = 0; g < ng; g++) run_group(B, y, gl[g], nsteps, dt, FPL_MODEL_HAMILTONIAN, 2, check);
    else
        for (int g = 0; g < ng; g++) run_group(B, y, gl[g], nsteps, dt, FPL_MODEL_HAMILTONIAN, B->k, check);
}

FPL_HOT static void run_groups_nonlinear(fpl_chaos_batch *B, double *y, const int *gl, int ng,
                                          long nsteps, double dt, int check)
{
    /* two deviation vectors (mLE + SALI), the usual case, get a build of their own */
    if (B->k == 2)
        for (int g = 0; g < ng; g++) run_group(B, y, gl[g], nsteps, dt, FPL_MODEL_NONLINEAR, 2, check);
    else
        for (int g = 0; g < ng; g++) run_group(B, y, gl[g], nsteps, dt, FPL_MODEL_NONLINEAR, B->k, check);
}

FPL_HOT static void run_groups_toda(fpl_chaos_batch *B, double *y, const int *gl, int ng,
                                    long nsteps, double dt, int check)
{
    if (B->k == 2)
        for (int g = 0; g < ng; g++) run_group(B, y, gl[g], nsteps, dt, FPL_MODEL_TODA, 2, check);
    else
        for (int g = 0; g < ng; g++) run_group(B, y, gl[g], nsteps, dt, FPL_MODEL_TODA, B->k, check);
}

/* ---- renormalisation over slots [0, ns) (chaos.c: norm2, sali_unit, gali_unit) ------------ */

/* The renormalisation works on whole groups with the lane values as generic vectors (vd):
 * element-wise sqrt, division and min are IEEE-exact per lane, and the sums are chaos_terms.h's,
 * which chaos.c runs on one orbit: each lane gets the single orbit's numbers. */
FPL_INLINE void vsqrt(vd *x)
{
    for (int w = 0; w < LANES; w++) (*x)[w] = sqrt((*x)[w]);
}
#define VSQRT(v) vsqrt(&(v))
#define AT_WV(r) VC(ROW(wv, r))
#define AT_QA(r) VC(ROW(qg, r))
#define AT_QB(r) VC(ROW(qg, len + (r)))
#define AT_QG(i, r) V(ROW(qg + (size_t)len * (size_t)(i) * LANES, r))
#define NOTE_ZERO_LANES(rr) \
    do { for (int w_ = 0; w_ < LANES; w_++) zero[w_] = (rr)[w_] == 0.0 ? 1.0 : zero[w_]; } while (0)

/* nrm[i S + s] = ||w_i|| of slot s, fin[s] = 0 if the slot's orbit is finite (NaN otherwise);
 * slots [0, ns), ns a multiple of LANES. */
FPL_HOT static void slot_norms(const fpl_chaos_batch *B, const double *y, int ns)
{
    const int n = B->n, k = B->k;
    const size_t S = (size_t)B->S, rows = (size_t)B->rows;
    for (int g = 0; g < ns / LANES; g++) {
        const double *yg = y + (size_t)g * rows * LANES;
        vd fin = {0};
        for (int r = 0; r < 2 * n; r++) fin += VC(ROW(yg, r)) * 0.0;
        V(B->fin + g * LANES) = fin;
        for (int i = 0; i < k; i++) {
            const double *wv = yg + (size_t)2 * n * (i + 1) * LANES;
            vd acc = {0};
            FPL_SUM_SQUARES(acc, 2 * n, AT_WV);
            vsqrt(&acc);
            V(B->nrm + (size_t)i * S + g * LANES) = acc;
        }
    }
}

/* q_i = w_i / ||w_i||, SALI(q_0, q_1) into acc1, GALI_k into gali (chaos.c: sali_unit,
 * gali_unit, per slot). */
FPL_HOT static void slot_indices(const fpl_chaos_batch *B, const double *y, int ns)
{
    const int n = B->n, k = B->k, len = 2 * n;
    const size_t S = (size_t)B->S, rows = (size_t)B->rows;
    for (int g = 0; g < ns / LANES; g++) {
        const double *yg = y + (size_t)g * rows * LANES;
        double *qg = B->q + (size_t)g * len * k * LANES;
        for (int i = 0; i < k; i++) {
            const double *wv = yg + (size_t)len * (i + 1) * LANES;
            double *q = qg + (size_t)len * i * LANES;
            const vd nr = VC(B->nrm + (size_t)i * S + g * LANES);
            for (int r = 0; r < len; r++) V(ROW(q, r)) = VC(ROW(wv, r)) / nr;
        }
        if (k < 2) continue;
        vd dm = {0}, dp = {0};
        FPL_SALI_SUMS(dm, dp, len, AT_QA, AT_QB);
        vd mn;
        for (int w = 0; w < LANES; w++) mn[w] = fmin(dm[w], dp[w]);
        vsqrt(&mn);
        V(B->acc1 + g * LANES) = mn;
        /* GALI by modified Gram-Schmidt; a zero pivot gives 0 */
        vd prod, zero = {0};
        for (int w = 0; w < LANES; w++) prod[w] = 1.0;
        FPL_GALI_MGS(k, len, AT_QG, prod, (vd){0}, VSQRT, NOTE_ZERO_LANES);
        for (int w = 0; w < LANES; w++) B->gali[g * LANES + w] = zero[w] != 0.0 ? 0.0 : prod[w];
    }
}

/* w_i *= inv[i S + s] (fpl_integrator_transform_deviations with a diagonal matrix: the zero
 * entries add exact zeros, so the product is the same number). */
FPL_HOT static void slot_scale(fpl_chaos_batch *B, int ns)
{
    const int n = B->n, k = B->k, len = 2 * n;
    const size_t S = (size_t)B->S, rows = (size_t)B->rows;
    for (int g = 0; g < ns / LANES; g++) {
        for (int i = 0; i < k; i++) {
            double *wv = B->y + (size_t)g * rows * LANES + (size_t)len * (i + 1) * LANES;
            const vd sc = VC(B->inv + (size_t)i * S + g * LANES);
            for (int r = 0; r < len; r++) V(ROW(wv, r)) *= sc;
        }
    }
}

/* ---- lanes ------------------------------------------------------------------------------- */

/* Element (row, slot s) of an array of `rows` rows: [group][row][lane]. */
static size_t at(long rows, long row, int s)
{
    return ((size_t)(s / LANES) * (size_t)rows + (size_t)row) * LANES + (size_t)(s % LANES);
}

static void slot_get(const fpl_chaos_batch *B, const double *y, int s, double *out)
{
    const double *base = y + at(B->rows, 0, s);
    for (long r = 0; r < B->rows; r++) out[r] = base[(size_t)r * LANES];
}

static void slot_put(fpl_chaos_batch *B, int s, const double *in)
{
    for (long r = 0; r < B->rows; r++) B->y[at(B->rows, r, s)] = in[r];
}

static void slot_coefficients(fpl_chaos_batch *B, int s, const fpl_lattice *lat)
{
    for (int j = 0; j < B->n; j++) {
        const size_t i = at(B->n, j, s);
        B->cl[i] = lat ? lat->cl[j] : 1.0;
        B->cn[i] = lat ? lat->cn[j] : 1.0;
        B->sc[i] = lat ? lat->s[j] : 1.0;
        B->minv[i] = lat ? lat->minv[j] : 1.0;
    }
}

/* Empty slot: zero state and unit coefficients (stays finite and costs no NaN arithmetic). */
static void slot_clear(fpl_chaos_batch *B, int s)
{
    for (long r = 0; r < B->rows; r++) B->y[at(B->rows, r, s)] = 0.0;
    slot_coefficients(B, s, NULL);
    B->orbit_of_slot[s] = -1;
}

static void slot_move(fpl_chaos_batch *B, int from, int to)
{
    for (long r = 0; r < B->rows; r++) B->y[at(B->rows, r, to)] = B->y[at(B->rows, r, from)];
    const int o = B->orbit_of_slot[from];
    slot_coefficients(B, to, B->lat[o]);
    B->orbit_of_slot[to] = o;
    B->slot_of_orbit[o] = to;
}

/* The lane stops; its state (from src, the batch state or the interval-start backup) is kept. */
static void finish_lane(fpl_chaos_batch *B, int o, const double *src)
{
    const long lane = 2L * B->n * (B->k + 1);
    if (B->slot_of_orbit[o] >= 0) slot_get(B, src, B->slot_of_orbit[o], B->final_y + (size_t)o * lane);
    B->res[o].done = 1;
    B->pending[o] = 0;
    B->n_active--;
}

/* The slots of finished lanes are emptied (compact mode) and the running lanes moved into the
 * first n_active slots. */
static void compact(fpl_chaos_batch *B)
{
    if (!B->compact) return;
    for (int s = 0; s < B->S; s++) {
        int o = B->orbit_of_slot[s];
        if (o >= 0 && B->res[o].done) {
            B->slot_of_orbit[o] = -1;
            B->orbit_of_slot[s] = -1;
            B->vacated[s] = 1;
        }
    }
    int to = 0;
    for (int s = 0; s < B->S; s++) {
        if (B->orbit_of_slot[s] < 0) continue;
        if (s != to) {
            slot_move(B, s, to);
            B->orbit_of_slot[s] = -1;
            B->vacated[s] = 1;
        }
        B->vacated[to] = 0;
        to++;
    }
    /* vacated slots get a zero state (no NaN arithmetic in the group's padding) */
    for (int s = to; s < B->S; s++)
        if (B->vacated[s]) {
            slot_clear(B, s);
            B->vacated[s] = 0;
        }
}

/* A group with a single running lane costs four lanes; from N = LONE_MIN_N on, that lane is
 * cheaper stepped alone by the single-orbit code (splitting.c, vectorised along the chain), on a
 * copy in the lattice's layout: the same arithmetic, so the same numbers. */
#define LONE_MIN_N 12

static void run_lone(fpl_chaos_batch *B, double *y, int s, long nsteps, double dt, int check)
{
    const int o = B->orbit_of_slot[s];
    const fpl_splitting *sch = B->scheme;
    fpl_split_run run;                /* kinetic-drift schemes: no state, nothing allocated */
    fpl_split_run_init(&run, sch, B->lat[o], B->work, B->k);
    double *ly = B->lane_y;
    slot_get(B, y, s, ly);
    for (long done = 0; done < nsteps;) {
        long block = B->ev.n > 0 && check
                         ? (nsteps - done < FPL_EVENT_BLOCK ? nsteps - done : FPL_EVENT_BLOCK)
                         : nsteps - done;
        fpl_split_steps(sch, &run.sys, ly, dt, block);
        done += block;
        if (B->ev.n > 0 && check && !B->fired[s]) {
            double g[8];
            fpl_events_eval(run.lc.lat, B->work, &B->ev, ly, g);
            for (int c = 0; c < B->ev.n; c++)
                if (!(g[c] > 0.0)) {
                    B->fired[s] = 1;
                    B->fired_step[s] = done;
                }
        }
    }
    double *base = y + at(B->rows, 0, s);
    for (long r = 0; r < B->rows; r++) base[(size_t)r * LANES] = ly[r];
}

/* Advance the groups with running lanes (B->groups[0..ng)) by nsteps steps of dt; check the
 * criteria on the way if `check`. */
static void run_groups(fpl_chaos_batch *B, double *y, int ng, long nsteps, double dt, int check)
{
    if (nsteps <= 0 || ng <= 0) return;
    int nv = 0;
    for (int g = 0; g < ng; g++) {
        int running = 0, slot = -1;
        for (int w = 0; w < LANES; w++) {
            const int s = B->groups[g] * LANES + w, o = B->orbit_of_slot[s];
            if (o >= 0 && !B->res[o].done) { running++; slot = s; }
        }
        if (running == 1 && B->n >= LONE_MIN_N) run_lone(B, y, slot, nsteps, dt, check);
        else B->vgroups[nv++] = B->groups[g];
    }
    if (nv == 0) return;
    if (B->model == FPL_MODEL_HOMOGENEOUS) run_groups_homogeneous(B, y, B->vgroups, nv, nsteps, dt, check);
    else if (B->model == FPL_MODEL_HAMILTONIAN) run_groups_hamiltonian(B, y, B->vgroups, nv, nsteps, dt, check);
    else if (B->model == FPL_MODEL_NONLINEAR) run_groups_nonlinear(B, y, B->vgroups, nv, nsteps, dt, check);
    else run_groups_toda(B, y, B->vgroups, nv, nsteps, dt, check);
}

/* Groups with at least one running lane. */
static int active_groups(fpl_chaos_batch *B)
{
    int ng = 0;
    for (int g = 0; g < B->S / LANES; g++) {
        int any = 0;
        for (int w = 0; w < LANES; w++) {
            int o = B->orbit_of_slot[g * LANES + w];
            any |= o >= 0 && !B->res[o].done;
        }
        if (any) B->groups[ng++] = g;
    }
    return ng;
}

/* Lane o in slot s blew up between the interval start (state in backup, at step n_start) and
 * the detection: replay it alone with fpl_integrator from the interval start, as a single-orbit
 * run would, to place the event in time and get the same account. */
static void blowup_lane(fpl_chaos_batch *B, int o, int s, long n_start, double t_interval,
                        double t_seen, int with_backup)
{
    fpl_chaos_batch_result *r = &B->res[o];
    r->blew_up = 1;
    r->chaotic = r->chaotic && !B->pending[o];
    if (B->pending[o]) r->t_chaotic = NAN;
    r->blowup_reason = FPL_BATCH_BLOWUP_NONFINITE;
    r->t_blowup = t_seen;
    r->event_index = -1;
    r->steps = n_start;
    finish_lane(B, o, with_backup ? B->backup : B->y);
    const double t_start = B->t0 + (double)n_start * B->dt;
    snprintf(B->msg[o], MSG_LEN, "blow-up: the state became non-finite between t = %.10g and "
             "t = %.10g", t_start, t_seen);
    if (with_backup) {
        slot_get(B, B->backup, s, B->lane_y);
        fpl_integrator_options io;
        fpl_integrator_options_init(&io);
        io.dt = B->dt;
        io.events = &B->ev;
        fpl_integrator *h = NULL;
        int st = fpl_integrator_create(B->lat[o], B->scheme->name, B->k, &io, t_start, B->lane_y, &h);
        if (st == FPL_OK) {
            st = fpl_integrator_advance(h, t_interval, B->lane_y);
            int idx = -1;
            double tev = NAN;
            if (st == FPL_EVENT && fpl_integrator_event(h, &idx, &tev)) {
                r->blowup_reason = FPL_BATCH_BLOWUP_EVENT;
                r->event_index = idx;
                r->t_blowup = tev;
                snprintf(B->msg[o], MSG_LEN, "blow-up: stopping criterion '%s' fired at t = %.10g",
                         B->ev_desc[idx], tev);
            } else if (st == FPL_ERR_NONFINITE) {
                snprintf(B->msg[o], MSG_LEN, "blow-up: the state became non-finite before t = %.10g "
                         "(%s)", t_interval, fpl_last_error());
            } else if (B->ev.n > 0 && st == FPL_OK) {
                /* the replay saw nothing (a crossing within round-off): the batch's check holds */
                r->blowup_reason = FPL_BATCH_BLOWUP_EVENT;
                snprintf(B->msg[o], MSG_LEN, "blow-up: a stopping criterion fired by t = %.10g", t_seen);
            }
            r->steps = n_start + fpl_integrator_steps(h);
        }
        fpl_integrator_free(&h);
    }
    /* as fpl_chaos: a non-finite state is dated by the renormalisation that found it */
    if (r->blowup_reason == FPL_BATCH_BLOWUP_NONFINITE) r->t_blowup = t_interval;
}

/* max_b |x_{b+1} - x_b| of slot s's orbit, ends included (chaos.c: max_stretch); NaN if the
 * orbit is not finite. */
static double slot_max_stretch(const fpl_chaos_batch *B, const double *y, int s)
{
    const int n = B->n;
    const double *x = y + at(B->rows, 0, s);
    const double xe = x[(size_t)(n - 1) * LANES];
    double mx = B->ring ? fabs(x[0] - xe) : fabs(x[0]), nonfinite = 0.0;
    for (int j = 0; j + 1 < n; j++) {
        const double d = fabs(x[(size_t)(j + 1) * LANES] - x[(size_t)j * LANES]);
        mx = d > mx ? d : mx;
        nonfinite += x[(size_t)j * LANES] - x[(size_t)j * LANES];
    }
    if (!B->ring) mx = fabs(xe) > mx ? fabs(xe) : mx;
    return mx + nonfinite + (xe - xe);
}

static void stretch_blowup(fpl_chaos_batch *B, int o, double t, long n_steps)
{
    fpl_chaos_batch_result *r = &B->res[o];
    r->blew_up = 1;
    if (B->pending[o]) r->t_chaotic = NAN;
    r->blowup_reason = FPL_BATCH_BLOWUP_STRETCH;
    r->t_blowup = t;
    r->event_index = -1;
    r->steps = n_steps;
    finish_lane(B, o, B->y);
}

/* ---- create / free ------------------------------------------------------------------------ */

void fpl_chaos_batch_free(fpl_chaos_batch **bp)
{
    if (!bp || !*bp) return;
    fpl_chaos_batch *B = *bp;
    free(B->lat);
    fpl_work_free(&B->work);
    free(B->orbit_of_slot);
    free(B->slot_of_orbit);
    free(B->y);
    free(B->backup);
    free(B->part);
    free(B->q);
    free(B->cl);
    free(B->cn);
    free(B->sc);
    free(B->minv);
    free(B->phi);
    free(B->kap);
    free(B->dphi);
    free(B->nrm);
    free(B->inv);
    free(B->acc1);
    free(B->acc2);
    free(B->gali);
    free(B->fin);
    free(B->fired);
    free(B->vacated);
    free(B->fired_step);
    free(B->lane_y);
    free(B->final_y);
    free(B->groups);
    free(B->vgroups);
    free(B->logsum);
    free(B->megno_acc);
    free(B->next);
    free(B->pending);
    free(B->res);
    free(B->msg);
    free(B);
    *bp = NULL;
}

static int check_args(fpl_lattice *const *lattices, int R, const char *method,
                      const fpl_integrator_options *io, double t0, const double *y0,
                      const fpl_chaos_batch_options *bo, const fpl_splitting **scheme, double *dt)
{
    if (R < 1) return fpl_error(NULL, FPL_ERR_ARG, "n_orbits must be >= 1 (got %d)", R);
    if (!lattices) return fpl_error(NULL, FPL_ERR_ARG, "lattices: NULL pointer");
    if (!bo) return fpl_error(NULL, FPL_ERR_ARG, "opt: NULL options");
    const fpl_chaos_options *o = &bo->chaos;
    if (!y0) return fpl_error(NULL, FPL_ERR_ARG, "y0: NULL pointer");
    for (int r = 0; r < R; r++) {
        const fpl_lattice *l = lattices[r], *l0 = lattices[0];
        if (!l) return fpl_error(NULL, FPL_ERR_ARG, "lattices[%d]: NULL handle", r);
        if (l->boundary != l0->boundary)
            return fpl_error(NULL, FPL_ERR_ARG, "lattices[%d]: boundary differs from lattices[0]: "
                             "a batch holds orbits of one boundary condition", r);
        if (l->n != l0->n)
            return fpl_error(NULL, FPL_ERR_ARG, "lattices[%d]: N = %d differs from lattices[0] "
                             "(N = %d): a batch holds orbits of one N", r, l->n, l0->n);
        if (l->ops->model != l0->ops->model)
            return fpl_error(NULL, FPL_ERR_ARG, "lattices[%d]: model '%s' differs from lattices[0] "
                             "('%s'): a batch holds orbits of one model", r, l->ops->name,
                             l0->ops->name);
        if (l->alpha != l0->alpha || l->beta != l0->beta)
            return fpl_error(NULL, FPL_ERR_ARG, "lattices[%d]: alpha, beta = %g, %g differ from "
                             "lattices[0] (%g, %g)", r, l->alpha, l->beta, l0->alpha, l0->beta);
    }
    const fpl_event_set *ev = io ? io->events : NULL;
    int st = fpl_events_check(ev, lattices[0]->n);
    if (st) return st;
    for (int i = 0; ev && i < ev->n; i++)
        if (ev->kind[i] == FPL_EVENT_MODE_ENERGY)
            return fpl_error(NULL, FPL_ERR_ARG, "events: criterion %d (mode energy) is not "
                             "supported by the batch kernel (use stretch, displacement or energy)", i);
    if (!method) return fpl_error(NULL, FPL_ERR_ARG, "method: NULL name");
    const fpl_splitting *sch = NULL;
    fpl_splitting_lookup(method, &sch);
    if (!sch || sch->run_setup) {
        int order, adaptive;
        int known = fpl_method_info(method, &order, &adaptive) == FPL_OK;
        char names[256] = "";
        for (int i = 0; i < fpl_chaos_batch_method_count(); i++) {
            size_t used = strlen(names);
            snprintf(names + used, sizeof names - used, "%s%s", i ? ", " : "",
                     fpl_chaos_batch_method_name(i));
        }
        return fpl_error(NULL, known ? FPL_ERR_ARG : FPL_ERR_UNKNOWN,
                         "method '%s' %s: the batch kernel runs the kinetic-drift splitting schemes "
                         "(%s)", method, known ? "is not supported" : "is unknown", names);
    }
    *scheme = sch;
    *dt = io ? io->dt : 0.01;
    if (!(*dt > 0.0) || !isfinite(*dt))
        return fpl_error(NULL, FPL_ERR_ARG, "dt must be finite and > 0 (got %g)", *dt);
    if (!isfinite(t0)) return fpl_error(NULL, FPL_ERR_ARG, "t0 must be finite (got %g)", t0);
    if (!(o->t_end > t0) || !isfinite(o->t_end))
        return fpl_error(NULL, FPL_ERR_ARG, "t_end must be finite and > t0 = %g (got %g)", t0,
                         o->t_end);
    if ((o->t_end - t0) / *dt > 9e18)
        return fpl_error(NULL, FPL_ERR_ARG, "t_end = %g needs more than 9e18 steps of dt = %g "
                         "(the step counter is 64-bit)", o->t_end, *dt);
    if (!(o->renorm_interval > 0.0) || !isfinite(o->renorm_interval))
        return fpl_error(NULL, FPL_ERR_ARG, "renorm_interval must be finite and > 0 (got %g)",
                         o->renorm_interval);
    if (o->renorm_interval < *dt * (1 - 1e-12))
        return fpl_error(NULL, FPL_ERR_ARG, "renorm_interval = %g must be >= dt = %g",
                         o->renorm_interval, *dt);
    if (o->n_samples < 1)
        return fpl_error(NULL, FPL_ERR_ARG, "n_samples must be >= 1 (got %d)", o->n_samples);
    if (!(o->t_first_sample >= 0.0) || !isfinite(o->t_first_sample))
        return fpl_error(NULL, FPL_ERR_ARG, "t_first_sample must be finite and >= 0 (got %g)",
                         o->t_first_sample);
    if (o->n_dev < 1) return fpl_error(NULL, FPL_ERR_ARG, "n_dev must be >= 1 (got %d)", o->n_dev);
    if (lattices[0]->n > INT_MAX / 2)   /* 2N is an int below */
        return fpl_error(NULL, FPL_ERR_ARG, "N = %d is too large for a batch (2N must fit an int)",
                         lattices[0]->n);
    if (o->n_dev > 2 * lattices[0]->n)
        return fpl_error(NULL, FPL_ERR_ARG, "n_dev = %d exceeds the phase-space dimension 2N = %d",
                         o->n_dev, 2 * lattices[0]->n);
    if (!isfinite(o->blowup_stretch))
        return fpl_error(NULL, FPL_ERR_ARG, "blowup_stretch must be finite (got %g)",
                         o->blowup_stretch);
    if (!(o->sali_threshold >= 0.0))
        return fpl_error(NULL, FPL_ERR_ARG, "sali_threshold must be >= 0 (got %g)",
                         o->sali_threshold);
    return FPL_OK;
}

/* Zeroed, 32-byte aligned (whole vd rows), never of size 0. */
static void *zalloc(size_t count, size_t size)
{
    size_t bytes = (count > 0 ? count : 1) * size;
    bytes = (bytes + 31) / 32 * 32;
    void *p = aligned_alloc(32, bytes);
    if (p) memset(p, 0, bytes);
    return p;
}
#define ALLOC(p, count) ((p) = zalloc((size_t)(count), sizeof *(p)))

int fpl_chaos_batch_create(fpl_lattice *const *lattices, int R, const char *method,
                           const fpl_integrator_options *io, double t0, const double *y0,
                           const double *w0, const fpl_chaos_batch_options *opt,
                           fpl_chaos_batch **out)
{
    if (!out) return fpl_error(NULL, FPL_ERR_ARG, "out: NULL pointer");
    *out = NULL;
    const fpl_splitting *scheme = NULL;
    double dt = 0.0;
    int st = check_args(lattices, R, method, io, t0, y0, opt, &scheme, &dt);
    if (st) return st;
    const int n = lattices[0]->n, k = opt->chaos.n_dev, len = 2 * n;
    long bad, rows;
    /* the lanes hold R (rounded up) states of 2N(1 + n_dev), twice (state and backup) */
    if ((st = fpl_state_length(n, k, &rows)) ||
        (st = fpl_check_alloc((size_t)rows, 2 * ((size_t)R + LANES) * sizeof(double),
                              "the batch's R states with their deviation vectors")))
        return st;
    if (!fpl_is_finite_array(y0, (long)R * len, &bad))
        return fpl_error(NULL, FPL_ERR_ARG, "y0[%ld][%ld] is not finite", bad / len, bad % len);
    if (w0 && !fpl_is_finite_array(w0, (long)R * k * len, &bad))
        return fpl_error(NULL, FPL_ERR_ARG, "w0[%ld][%ld][%ld] is not finite", bad / ((long)k * len),
                         bad / len % k, bad % len);
    fpl_chaos_batch *B = calloc(1, sizeof *B);
    if (!B) return fpl_error(NULL, FPL_ERR_NOMEM, "out of memory (chaos batch)");
    B->R = R;
    B->n = n;
    B->k = k;
    B->model = lattices[0]->ops->model;
    B->ring = lattices[0]->boundary == FPL_BOUNDARY_PERIODIC;
    B->S = (R + LANES - 1) / LANES * LANES;
    B->rows = (long)len * (k + 1);
    B->alpha = lattices[0]->alpha;
    B->beta = lattices[0]->beta;
    B->dt = dt;
    B->t0 = t0;
    B->T = opt->chaos.t_end - t0;
    B->tau = opt->chaos.renorm_interval;
    B->t_first = opt->chaos.t_first_sample > 0.0 ? opt->chaos.t_first_sample : fmin(opt->chaos.renorm_interval, B->T);
    B->n_renorm = (long)ceil(B->T / opt->chaos.renorm_interval - 1e-9);
    B->scheme = scheme;
    B->opt = opt->chaos;
    B->compact = opt->compact;
    if (io && io->events) B->ev = *io->events;
    for (int i = 0; i < B->ev.n; i++)
        fpl_events_describe(&B->ev, i, B->ev_desc[i], sizeof B->ev_desc[i]);
    /* automatic (0): the potential's nearest barrier, none if it has none, as fpl_chaos */
    const double barrier = fpl_barrier_stretch(lattices[0]);
    B->stretch_limit = opt->chaos.blowup_stretch > 0 ? opt->chaos.blowup_stretch
                     : opt->chaos.blowup_stretch == 0 && isfinite(barrier) ? barrier : 0.0;
    const size_t S = (size_t)B->S, dim = (size_t)len * (k + 1) * S;
    ALLOC(B->lat, R);
    if (fpl_work_create(n, 0, &B->work) != FPL_OK ||
        fpl_work_reserve_vectors(B->work, k) != FPL_OK) {
        fpl_chaos_batch_free(&B);
        return FPL_ERR_NOMEM;
    }
    ALLOC(B->orbit_of_slot, S);
    ALLOC(B->slot_of_orbit, R);
    ALLOC(B->y, dim);
    ALLOC(B->part, dim);
    if (B->ev.n > 0) ALLOC(B->backup, dim);
    ALLOC(B->q, (size_t)len * k * S);
    ALLOC(B->cl, (size_t)n * S);
    ALLOC(B->cn, (size_t)n * S);
    ALLOC(B->sc, (size_t)n * S);
    ALLOC(B->minv, (size_t)n * S);
    ALLOC(B->phi, (size_t)(n + 1) * LANES);
    ALLOC(B->kap, (size_t)(n + 1) * LANES);
    ALLOC(B->dphi, (size_t)(n + 1 > 2 * k ? n + 1 : 2 * k) * LANES);
    ALLOC(B->nrm, (size_t)k * S);
    ALLOC(B->inv, (size_t)k * S);
    ALLOC(B->acc1, S);
    ALLOC(B->acc2, S);
    ALLOC(B->gali, S);
    ALLOC(B->fin, 2 * S);
    ALLOC(B->fired, S);
    ALLOC(B->vacated, S);
    ALLOC(B->fired_step, S);
    ALLOC(B->lane_y, (size_t)len * (k + 1));
    ALLOC(B->final_y, (size_t)len * (k + 1) * R);
    ALLOC(B->groups, S / LANES);
    ALLOC(B->vgroups, S / LANES);
    ALLOC(B->logsum, R);
    ALLOC(B->megno_acc, (size_t)3 * R);
    ALLOC(B->next, R);
    ALLOC(B->pending, R);
    ALLOC(B->res, R);
    ALLOC(B->msg, R);
    if (!B->lat || !B->orbit_of_slot || !B->slot_of_orbit || !B->y || !B->part ||
        (B->ev.n > 0 && !B->backup) || !B->q || !B->cl || !B->cn || !B->sc || !B->minv ||
        !B->phi || !B->kap || !B->dphi || !B->nrm || !B->inv || !B->acc1 || !B->acc2 ||
        !B->gali || !B->fin || !B->fired || !B->vacated || !B->fired_step || !B->lane_y || !B->final_y || !B->groups || !B->vgroups ||
        !B->logsum || !B->megno_acc || !B->next || !B->pending || !B->res || !B->msg) {
        fpl_chaos_batch_free(&B);
        return fpl_error(NULL, FPL_ERR_NOMEM, "out of memory (chaos batch of %d orbits, N = %d)",
                         R, n);
    }
    /* deviation vectors: as chaos.c (Gaussian from the seed, then each divided by its norm) */
    double *w = B->lane_y + len, *random = B->q; /* q is free until the first renormalisation */
    if (!w0) {
        gsl_rng *rng = gsl_rng_alloc(gsl_rng_mt19937);
        if (!rng) { fpl_chaos_batch_free(&B); return fpl_error(NULL, FPL_ERR_NOMEM, "RNG"); }
        gsl_rng_set(rng, opt->chaos.seed);
        for (long i = 0; i < (long)len * k; i++) random[i] = gsl_ran_gaussian(rng, 1.0);
        gsl_rng_free(rng);
    }
    for (int s = 0; s < B->S; s++) slot_clear(B, s);
    for (int r = 0; r < R; r++) {
        B->lat[r] = lattices[r];
        memcpy(B->lane_y, y0 + (size_t)r * len, sizeof(double) * (size_t)len);
        memcpy(w, w0 ? w0 + (size_t)r * k * len : random, sizeof(double) * (size_t)len * k);
        for (int i = 0; i < k; i++) {
            double *wi = w + (size_t)len * i, s2 = 0.0;
            for (int c = 0; c < len; c++) s2 += wi[c] * wi[c];
            double nn = sqrt(s2);
            if (!(nn > 0.0) || !isfinite(nn)) {
                fpl_chaos_batch_free(&B);
                return fpl_error(NULL, FPL_ERR_ARG, "w0[%d][%d]: deviation vector must be finite and "
                                 "non-zero", r, i);
            }
            for (int c = 0; c < len; c++) wi[c] /= nn;
        }
        slot_put(B, r, B->lane_y);
        slot_coefficients(B, r, lattices[r]);
        B->orbit_of_slot[r] = r;
        B->slot_of_orbit[r] = r;
        B->res[r] = (fpl_chaos_batch_result){0, t0, NAN, NAN, NAN, 0, NAN, 0, NAN,
                                             FPL_BATCH_BLOWUP_NONE, -1, 0, 0, NAN};
        B->megno_acc[3 * r] = B->megno_acc[3 * r + 1] = B->megno_acc[3 * r + 2] = 0.0;
    }
    B->n_active = R;
    /* a criterion that holds at t0 stops the lane there, as fpl_integrator_advance would */
    if (B->ev.n > 0) {
        double g[8];
        for (int r = 0; r < R; r++) {
            fpl_events_eval(lattices[r], B->work, &B->ev, y0 + (size_t)r * len, g);
            for (int i = 0; i < B->ev.n; i++) {
                if (g[i] <= 0.0 && !B->res[r].done) {
                    B->res[r].blew_up = 1;
                    B->res[r].blowup_reason = FPL_BATCH_BLOWUP_EVENT;
                    B->res[r].event_index = i;
                    B->res[r].t_blowup = t0;
                    snprintf(B->msg[r], MSG_LEN, "blow-up: stopping criterion '%s' fired at t = %.10g "
                             "(the initial state)",
                             B->ev_desc[i], t0);
                    finish_lane(B, r, B->y);
                }
            }
        }
        compact(B);
    }
    *out = B;
    return FPL_OK;
}

/* ---- advance ------------------------------------------------------------------------------ */

static double sample_target(const fpl_chaos_batch *B, int i)
{
    const int n = B->opt.n_samples;
    return n == 1 ? B->T : B->t_first * pow(B->T / B->t_first, (double)i / (n - 1));
}

int fpl_chaos_batch_advance(fpl_chaos_batch *B, double t_until, double *t_out, double *mle_out,
                            double *sali_out, double *gali_out)
{
    return fpl_chaos_batch_advance_megno(B, t_until, t_out, mle_out, sali_out, gali_out, NULL);
}

int fpl_chaos_batch_advance_megno(fpl_chaos_batch *B, double t_until, double *t_out,
                                  double *mle_out, double *sali_out, double *gali_out,
                                  double *megno_out)
{
    if (!B) return fpl_error(NULL, FPL_ERR_ARG, "batch: NULL handle");
    if (!(t_until == t_until)) return fpl_error(NULL, FPL_ERR_ARG, "t_until must not be NaN");
    const int k = B->k, ns_max = B->opt.n_samples;
    const size_t S = (size_t)B->S, dim = (size_t)2 * B->n * (k + 1) * S;
    const double dt = B->dt;
    while (B->n_active > 0) {
        const long m = B->m + 1;
        const double t = m == B->n_renorm ? B->opt.t_end : B->t0 + (double)m * B->tau;
        if (t > t_until) break;
        const long n_target = (long)floor((t - B->t0) / dt + 1e-9), n_start = B->n_steps;
        const double rest = t - (B->t0 + (double)n_target * dt);
        const int ng = active_groups(B), ns = ng ? (B->groups[ng - 1] + 1) * LANES : 0;
        if (B->backup) memcpy(B->backup, B->y, sizeof(double) * dim);
        memset(B->fired, 0, S);
        run_groups(B, B->y, ng, n_target - n_start, dt, 1);
        B->n_steps = n_target;
        const double *yr = B->y;
        if (rest > 1e-9 * dt) {
            /* off the grid: one partial step from a copy, the grid state stays (as
             * fpl_integrator_advance does) */
            memcpy(B->part, B->y, sizeof(double) * dim);
            run_groups(B, B->part, ng, 1, rest, 0);
            if (B->ev.n > 0)
                for (int g = 0; g < ng; g++) {
                    unsigned char before[LANES];
                    int s0 = B->groups[g] * LANES;
                    memcpy(before, B->fired + s0, LANES);
                    check_group(B, group_at(B, B->part, B->groups[g]), B->fired + s0);
                    for (int w = 0; w < LANES; w++)
                        if (B->fired[s0 + w] && !before[w])
                            B->fired_step[s0 + w] = n_target - n_start + 1;
                }
            yr = B->part;
        }
        slot_norms(B, yr, ns);
        /* lanes that blew up in this interval */
        for (int s = 0; s < ns; s++) {
            const int o = B->orbit_of_slot[s];
            if (o < 0 || B->res[o].done) continue;
            int ok = B->fin[s] == 0.0;
            for (int i = 0; i < k; i++) {
                double nn = B->nrm[(size_t)i * S + s];
                ok = ok && nn > 0.0 && isfinite(nn);
            }
            if (B->fired[s]) {
                long fs = B->fired_step[s];
                double t_seen = fs > n_target - n_start ? t : B->t0 + (double)(n_start + fs) * dt;
                blowup_lane(B, o, s, n_start, t, t_seen, 1);
            } else if (!ok) {
                blowup_lane(B, o, s, n_start, t, t, B->backup != NULL);
            }
        }
        /* before SALI, as fpl_chaos: a bond stretched beyond the barrier is a runaway orbit */
        if (B->stretch_limit > 0) {
            for (int s = 0; s < ns; s++) {
                const int o = B->orbit_of_slot[s];
                if (o < 0 || B->res[o].done) continue;
                const double mx = slot_max_stretch(B, yr, s);
                if (!(mx <= B->stretch_limit)) {
                    stretch_blowup(B, o, t, n_target);
                    snprintf(B->msg[o], MSG_LEN, "blow-up: a bond stretch |x_{j+1} - x_j| = %.4g "
                             "exceeds %.4g at t = %.10g", mx, B->stretch_limit, t);
                }
            }
        }
        slot_indices(B, yr, ns);
        for (int s = 0; s < ns; s++) {
            const int o = B->orbit_of_slot[s];
            for (int i = 0; i < k; i++)
                B->inv[(size_t)i * S + s] = o >= 0 && !B->res[o].done ? 1.0 / B->nrm[(size_t)i * S + s] : 1.0;
        }
        slot_scale(B, ns);
        for (int s = 0; s < ns; s++) {
            const int o = B->orbit_of_slot[s];
            if (o < 0 || B->res[o].done) continue;
            fpl_chaos_batch_result *res = &B->res[o];
            const double ell_prev = B->logsum[o];
            B->logsum[o] += log(B->nrm[s]);
            /* as fpl_chaos: the interval from the previous renormalisation time */
            res->megno = fpl_megno_step(B->megno_acc + 3 * (size_t)o,
                                        t - (B->t0 + (double)(m - 1) * B->tau), t - B->t0,
                                        ell_prev, B->logsum[o]);
            res->mle = B->logsum[o] / (t - B->t0);
            res->t_final = t;
            res->steps = n_target;
            if (k >= 2) {
                res->sali = B->acc1[s];
                res->gali = B->gali[s];
                /* a SALI collapse counts once the orbit is still finite one interval later */
                if (B->pending[o]) {
                    res->chaotic = 1;
                    B->pending[o] = 0;
                }
                if (!res->chaotic && !B->pending[o] && res->sali < B->opt.sali_threshold) {
                    B->pending[o] = 1;
                    res->t_chaotic = t;
                }
                if (B->pending[o] && m == B->n_renorm) {
                    res->chaotic = 1;
                    B->pending[o] = 0;
                }
            }
            const int stop = B->opt.stop_when_chaotic && res->chaotic;
            if (B->next[o] < ns_max &&
                (t - B->t0 >= sample_target(B, B->next[o]) * (1 - 1e-12) || m == B->n_renorm || stop)) {
                const size_t at = (size_t)o * ns_max + res->n_samples;
                if (t_out) t_out[at] = t;
                if (mle_out) mle_out[at] = res->mle;
                if (sali_out) sali_out[at] = res->sali;
                if (gali_out) gali_out[at] = res->gali;
                if (megno_out) megno_out[at] = res->megno;
                res->n_samples++;
                while (B->next[o] < ns_max && sample_target(B, B->next[o]) <= (t - B->t0) * (1 + 1e-12))
                    B->next[o]++;
            }
            if (stop) snprintf(B->msg[o], MSG_LEN, "chaotic: SALI < %g at t = %.10g",
                               B->opt.sali_threshold, res->t_chaotic);
            if (stop || m == B->n_renorm) finish_lane(B, o, B->y);
        }
        B->m = m;
        compact(B);
    }
    return FPL_OK;
}

/* ---- queries ------------------------------------------------------------------------------ */

int fpl_chaos_batch_done(const fpl_chaos_batch *B) { return B ? B->n_active == 0 : 1; }
int fpl_chaos_batch_size(const fpl_chaos_batch *B) { return B ? B->R : 0; }
int fpl_chaos_batch_running(const fpl_chaos_batch *B) { return B ? B->n_active : 0; }

double fpl_chaos_batch_time(const fpl_chaos_batch *B)
{
    if (!B) return NAN;
    return B->m == 0 ? B->t0 : B->m == B->n_renorm ? B->opt.t_end : B->t0 + (double)B->m * B->tau;
}

static int check_orbit(const fpl_chaos_batch *B, int orbit)
{
    if (!B) return fpl_error(NULL, FPL_ERR_ARG, "batch: NULL handle");
    if (orbit < 0 || orbit >= B->R)
        return fpl_error(NULL, FPL_ERR_ARG, "orbit must be in 0..%d (got %d)", B->R - 1, orbit);
    return FPL_OK;
}

int fpl_chaos_batch_get_result(const fpl_chaos_batch *B, int orbit, fpl_chaos_batch_result *result)
{
    int st = check_orbit(B, orbit);
    if (st) return st;
    if (!result) return fpl_error(NULL, FPL_ERR_ARG, "result: NULL pointer");
    *result = B->res[orbit];
    return FPL_OK;
}

const char *fpl_chaos_batch_message(const fpl_chaos_batch *B, int orbit)
{
    if (!B || orbit < 0 || orbit >= B->R) return "";
    return B->msg[orbit];
}

int fpl_chaos_batch_get_state(const fpl_chaos_batch *B, int orbit, double *y)
{
    int st = check_orbit(B, orbit);
    if (st) return st;
    if (!y) return fpl_error(NULL, FPL_ERR_ARG, "y: NULL pointer");
    const long lane = 2L * B->n * (B->k + 1);
    if (B->res[orbit].done) memcpy(y, B->final_y + (size_t)orbit * lane, sizeof(double) * (size_t)lane);
    else slot_get(B, B->y, B->slot_of_orbit[orbit], y);
    return FPL_OK;
}

/* ---- checkpoints -------------------------------------------------------------------------- */

long fpl_chaos_batch_save_size(const fpl_chaos_batch *B)
{
    if (!B) return 0;
    return N_HEADER + (long)B->R * (N_LANE_ACC + 2L * B->n * (B->k + 1));
}

int fpl_chaos_batch_save(const fpl_chaos_batch *B, double *buf)
{
    if (!B || !buf) return fpl_error(NULL, FPL_ERR_ARG, "batch/buffer: NULL pointer");
    const long lane = 2L * B->n * (B->k + 1);
    double *h = buf;
    h[0] = SAVE_MAGIC; h[1] = B->R; h[2] = B->n; h[3] = B->k;
    h[4] = (double)B->n_steps; h[5] = (double)B->m; h[6] = B->n_active; h[7] = B->dt;
    double *p = buf + N_HEADER;
    for (int o = 0; o < B->R; o++) {
        const fpl_chaos_batch_result *r = &B->res[o];
        const double a[N_LANE_ACC] = {B->logsum[o], B->next[o], B->pending[o], r->n_samples,
            r->t_final, r->mle, r->sali, r->gali, r->chaotic, r->t_chaotic, r->blew_up,
            r->t_blowup, r->blowup_reason, r->event_index, (double)r->steps, r->done,
            B->slot_of_orbit[o] >= 0, B->megno_acc[3 * o], B->megno_acc[3 * o + 1],
            B->megno_acc[3 * o + 2], r->megno};
        memcpy(p, a, sizeof a);
        p += N_LANE_ACC;
        fpl_chaos_batch_get_state(B, o, p);
        p += lane;
    }
    return FPL_OK;
}

int fpl_chaos_batch_restore(fpl_chaos_batch *B, const double *buf, long len)
{
    if (!B || !buf) return fpl_error(NULL, FPL_ERR_ARG, "batch/buffer: NULL pointer");
    if (len != fpl_chaos_batch_save_size(B) || buf[0] != SAVE_MAGIC || buf[1] != B->R ||
        buf[2] != B->n || buf[3] != B->k || buf[7] != B->dt)
        return fpl_error(NULL, FPL_ERR_ARG, "buffer: not a checkpoint of this batch (%ld values; "
                         "expected %ld for %d orbits, N = %d, n_dev = %d, dt = %g)", len,
                         fpl_chaos_batch_save_size(B), B->R, B->n, B->k, B->dt);
    if (!(buf[5] >= 0 && buf[5] <= B->n_renorm) || buf[5] != floor(buf[5]) || !(buf[4] >= 0))
        return fpl_error(NULL, FPL_ERR_ARG, "buffer: renormalisation %g does not fit this run "
                         "(%ld renormalisations)", buf[5], B->n_renorm);
    const long lane = 2L * B->n * (B->k + 1);
    B->n_steps = (long)buf[4];
    B->m = (long)buf[5];
    B->n_active = 0;
    for (int s = 0; s < B->S; s++) slot_clear(B, s);
    const double *p = buf + N_HEADER;
    int slot = 0;
    for (int o = 0; o < B->R; o++, p += N_LANE_ACC + lane) {
        fpl_chaos_batch_result *r = &B->res[o];
        B->logsum[o] = p[0];
        B->next[o] = (int)p[1];
        B->pending[o] = p[2] != 0;
        r->n_samples = (int)p[3];
        r->t_final = p[4]; r->mle = p[5]; r->sali = p[6]; r->gali = p[7];
        r->chaotic = p[8] != 0; r->t_chaotic = p[9]; r->blew_up = p[10] != 0; r->t_blowup = p[11];
        r->blowup_reason = (int)p[12]; r->event_index = (int)p[13]; r->steps = (long)p[14];
        r->done = p[15] != 0;
        memcpy(B->megno_acc + 3 * (size_t)o, p + 17, sizeof(double) * 3);
        r->megno = p[20];
        B->msg[o][0] = '\0';
        if (r->blew_up && r->blowup_reason == FPL_BATCH_BLOWUP_EVENT && r->event_index >= 0 &&
            r->event_index < B->ev.n)
            snprintf(B->msg[o], MSG_LEN, "blow-up: stopping criterion '%s' fired at t = %.10g",
                     B->ev_desc[r->event_index], r->t_blowup);
        else if (r->blew_up && r->blowup_reason == FPL_BATCH_BLOWUP_STRETCH)
            snprintf(B->msg[o], MSG_LEN, "blow-up: a bond stretch |x_{j+1} - x_j| exceeded %.4g at "
                     "t = %.10g", B->stretch_limit, r->t_blowup);
        else if (r->blew_up)
            snprintf(B->msg[o], MSG_LEN, "blow-up: the state became non-finite by t = %.10g",
                     r->t_blowup);
        B->slot_of_orbit[o] = -1;
        if (r->done) {
            memcpy(B->final_y + (size_t)o * lane, p + N_LANE_ACC, sizeof(double) * (size_t)lane);
        } else {
            B->n_active++;
            slot_put(B, slot, p + N_LANE_ACC);
            slot_coefficients(B, slot, B->lat[o]);
            B->orbit_of_slot[slot] = o;
            B->slot_of_orbit[o] = slot;
            slot++;
        }
    }
    return FPL_OK;
}

/* ---- one orbit in the single-orbit checkpoint format ---------------------------------------
 * An orbit's state as fpl_chaos and its integrator keep it (step count, time, state with the
 * deviation vectors, the FPL_CHAOS_N_ACCUMULATORS numbers of fpl_chaos_save), so an orbit moves
 * between a lane and an fpl_chaos handle, or a file, without anyone outside knowing the lanes. A
 * lane computes exactly what fpl_chaos computes for its orbit; the only bookkeeping that differs
 * is where a lane keeps the time SALI fell below the threshold while it waits for confirmation
 * (its t_chaotic), which fpl_chaos keeps as t_pending. */

int fpl_chaos_batch_get_orbit(const fpl_chaos_batch *B, int orbit, long *steps, double *t,
                              double *y, double *acc)
{
    int st = check_orbit(B, orbit);
    if (st) return st;
    if (!steps || !t || !y || !acc)
        return fpl_error(NULL, FPL_ERR_ARG, "steps/t/y/accumulators: NULL pointer");
    const fpl_chaos_batch_result *r = &B->res[orbit];
    const int running = !r->done;
    const int chaotic = r->chaotic != 0, pending = B->pending[orbit] != 0;
    const double m = running ? (double)B->m : round((r->t_final - B->t0) / B->tau);
    const double a[FPL_CHAOS_N_ACCUMULATORS] = {
        m, B->logsum[orbit], B->next[orbit], r->n_samples, chaotic, chaotic ? r->t_chaotic : NAN,
        r->mle, r->sali, r->gali, r->t_final, r->done != 0, r->blew_up != 0, r->t_blowup,
        r->done && !r->blew_up, (pending || chaotic) ? r->t_chaotic : NAN,
        B->megno_acc[3 * (size_t)orbit], B->megno_acc[3 * (size_t)orbit + 1],
        B->megno_acc[3 * (size_t)orbit + 2], r->megno};
    memcpy(acc, a, sizeof a);
    *steps = running ? B->n_steps : r->steps;
    *t = running ? fpl_chaos_batch_time(B) : r->t_final;
    return fpl_chaos_batch_get_state(B, orbit, y);
}

int fpl_chaos_batch_set_orbits(fpl_chaos_batch *B, const long *steps, const double *t,
                               const double *y, const double *acc)
{
    if (!B) return fpl_error(NULL, FPL_ERR_ARG, "batch: NULL handle");
    if (!steps || !t || !y || !acc)
        return fpl_error(NULL, FPL_ERR_ARG, "steps/t/y/accumulators: NULL pointer");
    const long lane = 2L * B->n * (B->k + 1);
    const int NA = FPL_CHAOS_N_ACCUMULATORS;
    long common_steps = -1;
    double common_m = -1;
    int n_running = 0;
    for (int o = 0; o < B->R; o++) {
        const double *a = acc + (size_t)o * NA;
        if (a[10] != 0) continue;                        /* finished: keeps its result */
        const double m = a[0];
        if (!(m >= 0 && m <= B->n_renorm) || m != floor(m) || steps[o] < 0)
            return fpl_error(NULL, FPL_ERR_ARG, "orbit %d: renormalisation %g / step %ld do not fit "
                             "this run (%ld renormalisations)", o, m, steps[o], B->n_renorm);
        const double tm = m == B->n_renorm ? B->opt.t_end : B->t0 + m * B->tau;
        if (t[o] != tm)
            return fpl_error(NULL, FPL_ERR_ARG, "orbit %d: accumulators are for t = %.17g, the "
                             "state for t = %.17g", o, tm, t[o]);
        if (n_running++ == 0) {
            common_steps = steps[o];
            common_m = m;
        } else if (steps[o] != common_steps || m != common_m) {
            return fpl_error(NULL, FPL_ERR_ARG, "orbit %d is at step %ld, the running orbits "
                             "before it at step %ld: the running orbits of a batch share one time",
                             o, steps[o], common_steps);
        }
    }
    const long len = fpl_chaos_batch_save_size(B);
    double *buf = malloc(sizeof(double) * (size_t)len);
    if (!buf) return fpl_error(NULL, FPL_ERR_NOMEM, "batch: out of memory (%ld values)", len);
    buf[0] = SAVE_MAGIC; buf[1] = B->R; buf[2] = B->n; buf[3] = B->k;
    buf[4] = n_running ? (double)common_steps : (double)B->n_steps;
    buf[5] = n_running ? common_m : (double)B->m;
    buf[6] = n_running; buf[7] = B->dt;
    double *p = buf + N_HEADER;
    for (int o = 0; o < B->R; o++, p += N_LANE_ACC + lane) {
        const double *a = acc + (size_t)o * NA;
        const int chaotic = a[4] != 0, done = a[10] != 0;
        const int pending = !chaotic && a[14] == a[14];
        const double l[N_LANE_ACC] = {a[1], a[2], pending, a[3], a[9], a[6], a[7], a[8], chaotic,
            chaotic ? a[5] : pending ? a[14] : NAN, a[11] != 0, a[12],
            FPL_BATCH_BLOWUP_NONE, -1, (double)steps[o],
            done, !done, a[15], a[16], a[17], a[18]};
        memcpy(p, l, sizeof l);
        memcpy(p + N_LANE_ACC, y + (size_t)o * lane, sizeof(double) * (size_t)lane);
    }
    int st = fpl_chaos_batch_restore(B, buf, len);
    free(buf);
    return st;
}
