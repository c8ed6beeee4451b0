/* Dormand-Prince 8(5,3) "DOP853" as an ARKODE Butcher table: 12 stages (+ 1 FSAL stage, see
 * below), order 8, with the 5th-order embedding used for step-size control.
 *
 * Coefficients (full digits) from E. Hairer and G. Wanner's dop853.f
 * (http://www.unige.ch/~hairer/software.html; Hairer, Norsett & Wanner, "Solving Ordinary
 * Differential Equations I", 2nd ed., Springer 1993, Sec. II.10), as transcribed in SciPy's
 * scipy/integrate/_ivp/dop853_coefficients.py (arrays C, A, B = A[12, :12], E5).
 *
 * Hairer's code estimates the local error of the 8th-order solution with the "er" (SciPy: E5)
 * weights, err5 = h sum_i er_i k_i. ARKODE's estimate is y - yhat = h sum_i (b_i - d_i) k_i,
 * so the embedding is d = b - er. (dop853.f blends err5 with a 3rd-order estimate (bhh / E3);
 * ARKODE takes one embedding only, and we give it the 5th-order one.)
 *
 * A 13th stage is appended: c = 1, a_13j = b_j, weights 0, i.e. f(t + h, y_new), the
 * first-same-as-last evaluation dop853.f also makes (its k4 after the step). It costs nothing
 * (ERKStep reuses it as stage 1 of the next step) and it is needed: SUNDIALS 6.4's ERKStep
 * treats any table whose last node is c_s = 1 as FSAL and reuses the last stage's f as the
 * next step's first stage. With the 12-stage table that stage is f at an order-5 predictor,
 * not at y_new, and the method drops to order ~5.7 (measured: Kepler e = 0.5, fixed steps). */
#include <stdio.h> /* arkode_butcher.h uses FILE without including it */
#include <arkode/arkode_butcher.h>

ARKodeButcherTable fpl_dop853_table(void);

enum { S = 12, S_TABLE = 13 };

static const double c[S] = {
    0.0,
    0.526001519587677318785587544488e-01,
    0.789002279381515978178381316732e-01,
    0.118350341907227396726757197510,
    0.281649658092772603273242802490,
    0.333333333333333333333333333333,
    0.25,
    0.307692307692307692307692307692,
    0.651282051282051282051282051282,
    0.6,
    0.857142857142857142857142857142,
    1.0,
};

/* a[i][j], i > j (row i = stage i + 1 of dop853.f); zeros elsewhere. */
static const double a[S][S] = {
    [1] = {5.26001519587677318785587544488e-2},
    [2] = {1.97250569845378994544595329183e-2, 5.91751709536136983633785987549e-2},
    [3] = {2.95875854768068491816892993775e-2, 0.0, 8.87627564304205475450678981324e-2},
    [4] = {2.41365134159266685502369798665e-1, 0.0, -8.84549479328286085344864962717e-1,
           9.24834003261792003115737966543e-1},
    [5] = {3.7037037037037037037037037037e-2, 0.0, 0.0, 1.70828608729473871279604482173e-1,
           1.25467687566822425016691814123e-1},
    [6] = {3.7109375e-2, 0.0, 0.0, 1.70252211019544039314978060272e-1,
           6.02165389804559606850219397283e-2, -1.7578125e-2},
    [7] = {3.70920001185047927108779319836e-2, 0.0, 0.0, 1.70383925712239993810214054705e-1,
           1.07262030446373284651809199168e-1, -1.53194377486244017527936158236e-2,
           8.27378916381402288758473766002e-3},
    [8] = {6.24110958716075717114429577812e-1, 0.0, 0.0, -3.36089262944694129406857109825,
           -8.68219346841726006818189891453e-1, 2.75920996994467083049415600797e1,
           2.01540675504778934086186788979e1, -4.34898841810699588477366255144e1},
    [9] = {4.77662536438264365890433908527e-1, 0.0, 0.0, -2.48811461997166764192642586468,
           -5.90290826836842996371446475743e-1, 2.12300514481811942347288949897e1,
           1.52792336328824235832596922938e1, -3.32882109689848629194453265587e1,
           -2.03312017085086261358222928593e-2},
    [10] = {-9.3714243008598732571704021658e-1, 0.0, 0.0, 5.18637242884406370830023853209,
            1.09143734899672957818500254654, -8.14978701074692612513997267357,
            -1.85200656599969598641566180701e1, 2.27394870993505042818970056734e1,
            2.49360555267965238987089396762, -3.0467644718982195003823669022},
    [11] = {2.27331014751653820792359768449, 0.0, 0.0, -1.05344954667372501984066689879e1,
            -2.00087205822486249909675718444, -1.79589318631187989172765950534e1,
            2.79488845294199600508499808837e1, -2.85899827713502369474065508674,
            -8.87285693353062954433549289258, 1.23605671757943030647266201528e1,
            6.43392746015763530355970484046e-1},
};

/* 8th-order weights (dop853.f b1, b6..b12) */
static const double b[S] = {
    5.42937341165687622380535766363e-2, 0.0, 0.0, 0.0, 0.0,
    4.45031289275240888144113950566,
    1.89151789931450038304281599044,
    -5.8012039600105847814672114227,
    3.1116436695781989440891606237e-1,
    -1.52160949662516078556178806805e-1,
    2.01365400804030348374776537501e-1,
    4.47106157277725905176885569043e-2,
};

/* error weights er (dop853.f er1, er6..er12; SciPy E5) */
static const double er[S] = {
    0.1312004499419488073250102996e-1, 0.0, 0.0, 0.0, 0.0,
    -0.1225156446376204440720569753e1,
    -0.4957589496572501915214079952,
    0.1664377182454986536961530415e1,
    -0.3503288487499736816886487290,
    0.3341791187130174790297318841,
    0.8192320648511571246570742613e-1,
    -0.2235530786388629525884427845e-1,
};

/* A new table (the caller frees it with ARKodeButcherTable_Free), or NULL if out of memory. */
ARKodeButcherTable fpl_dop853_table(void)
{
    enum { T = S_TABLE };
    double cc[T] = {0}, aa[T * T] = {0}, bb[T] = {0}, dd[T] = {0};
    for (int i = 0; i < S; i++) {
        cc[i] = c[i];
        bb[i] = b[i];
        dd[i] = b[i] - er[i];
        for (int j = 0; j < S; j++) aa[i * T + j] = a[i][j];
        aa[S * T + i] = b[i];       /* FSAL stage: y_new */
    }
    cc[S] = 1.0;
    return ARKodeButcherTable_Create(T, 8, 5, cc, aa, bb, dd);
}
