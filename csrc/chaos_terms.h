/* The renormalisation's arithmetic of the chaos indicators, written once (private, not
 * installed): chaos.c evaluates it on one orbit's contiguous doubles, chaos_batch.c on a group
 * of lanes (GCC generic vectors, rows LANES apart), so a lane and a single orbit compute the same
 * operations in the same order and agree to the last bit (as model_terms.h for the kernels).
 * Macros rather than functions because the same code serves `double` and the lane vector type;
 * AT(r) / Q(i, r) name element r (of vector i) as an lvalue, ZERO is the type's zero, SQRT(v)
 * takes the square root of v in place (element-wise for lanes). */
#ifndef FPUTLAB_CHAOS_TERMS_H
#define FPUTLAB_CHAOS_TERMS_H

/* acc += sum_r AT(r)^2 over r = 0..len-1 in order (||w||^2; the norm is its square root). */
#define FPL_SUM_SQUARES(acc, len, AT)                                                       \
    do {                                                                                    \
        for (long r_ = 0; r_ < (long)(len); r_++) {                                         \
            const __typeof__(acc) x_ = AT(r_);                                              \
            (acc) += x_ * x_;                                                               \
        }                                                                                   \
    } while (0)

/* SALI's sums for unit vectors a = A(r), b = B(r): dm += |a - b|^2, dp += |a + b|^2; SALI is
 * sqrt(min(dm, dp)). */
#define FPL_SALI_SUMS(dm, dp, len, A, B)                                                    \
    do {                                                                                    \
        for (long r_ = 0; r_ < (long)(len); r_++) {                                         \
            const __typeof__(dm) a_ = A(r_), b_ = B(r_);                                    \
            (dm) += (a_ - b_) * (a_ - b_);                                                  \
            (dp) += (a_ + b_) * (a_ + b_);                                                  \
        }                                                                                   \
    } while (0)

/* GALI_k of k unit vectors Q(i, .) (overwritten): the product of the diagonal of R in W = QR by
 * modified Gram-Schmidt (accurate down to GALI ~ 1e-16, unlike the determinant of the Gram
 * matrix), into prod (which starts at 1). A zero pivot makes GALI 0: ON_ZERO(r) is evaluated
 * with every pivot r for the caller to note it (the sweep goes on through the then non-finite
 * values, which the caller discards). */
#define FPL_GALI_MGS(k, len, Q, prod, ZERO, SQRT, ON_ZERO)                                  \
    do {                                                                                    \
        for (int i_ = 0; i_ < (k); i_++) {                                                  \
            __typeof__(prod) rr_ = ZERO;                                                    \
            for (long r_ = 0; r_ < (long)(len); r_++) {                                     \
                const __typeof__(prod) x_ = Q(i_, r_);                                      \
                rr_ += x_ * x_;                                                             \
            }                                                                               \
            SQRT(rr_);                                                                      \
            (prod) *= rr_;                                                                  \
            ON_ZERO(rr_);                                                                   \
            for (long r_ = 0; r_ < (long)(len); r_++) Q(i_, r_) /= rr_;                     \
            for (int j_ = i_ + 1; j_ < (k); j_++) {                                         \
                __typeof__(prod) dot_ = ZERO;                                               \
                for (long r_ = 0; r_ < (long)(len); r_++) dot_ += Q(i_, r_) * Q(j_, r_);    \
                for (long r_ = 0; r_ < (long)(len); r_++) Q(j_, r_) -= dot_ * Q(i_, r_);    \
            }                                                                               \
        }                                                                                   \
    } while (0)

#endif
