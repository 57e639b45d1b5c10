/* chaplygin.numerics.dynamics.batch_map: the stroboscopic map of many points in one call, in C.
 *
 * Appended to a model's emitted C source (generated/<model>.c: chaplygin_rhs) followed by
 * templates/variational.c, whose DOP853 tableau (DOP_C, DOP_A, DOP_B, DOP_E3, DOP_E5) it
 * reuses (chaplygin.derive.emit.c_sources.batch_source puts them together, with bm_time
 * of templates/batch_time.c in its place below). Each of N points has its own state,
 * parameter vector and sampling times
 *     t_k = t0 + k tau,  tau = tau_hi + tau_lo (a double-double: tau to ~32 digits),
 * t_k rounded once from k tau_hi (exact product by fma) + k tau_lo + t0, so that t_k does not
 * accumulate k roundings. The plain system y' = f(t, y) is integrated by the adaptive DOP853 of
 * Hairer's dop853.f (the error estimate and step control of variational.c's chaplygin_var_flow,
 * on y alone), every step landing exactly on the next t_k; the step size is carried from one
 * period to the next. Points are independent: a point that fails (non-finite value, step
 * underflow, step limit) stops with its own status and the others go on.
 *
 * chaplygin_batch_map(N, Y0, P, T0, TAU_HI, TAU_LO, transient, n_record, rtol, atol,
 *                     max_steps, OUT, STATS, STATUS)
 *   Y0   N x n_state       initial states (row per point)
 *   P    N x n_param       parameters (row per point)
 *   OUT  N x n_record x n_state: y(t_k), k = transient .. transient + n_record - 1
 *        (all NaN for a point that failed)
 *   STATS N x 3: accepted steps, rejected steps, evaluations of f
 *   STATUS N: 0 done, 1 step limit (max_steps per period), 2 step-size underflow, 3 non-finite
 *
 * chaplygin_batch_map_lockstep(same arguments): the same computation, BM_W points at a time in
 * the lanes of GCC vector types (BM_VEC_RHS defined: bm_rhs_vec of generated/<model>_lanes.c,
 * appended after this file, is the emitted chaplygin_rhs with every double a vector of BM_W
 * lanes). Every lane takes its own
 * steps (own t, h, accept/reject, sampling times); the stage sums and the right-hand side run
 * on all lanes at once, each lane with the same IEEE operations in the same order as
 * chaplygin_batch_map (no contraction; detmath's sine and cosine written on vectors with the
 * scalar functions' bits, the other functions lane by lane), so the results are bit-identical
 * to it. A lane whose point is done (or failed) takes the next point of the batch. BM_W is 8
 * where the compiler targets AVX-512, else 4: the bits do not depend on it.
 */
#include <float.h>
#include <math.h>

#define BM_N CHAPLYGIN_N_STATE

/* RMS norm of v / (atol + rtol |y|) */
static double bm_norm(const double *v, const double *y, double rtol, double atol)
{
    double s = 0.0;
    for (int i = 0; i < BM_N; ++i) {
        double r = v[i] / (atol + rtol * fabs(y[i]));
        s += r * r;
    }
    return sqrt(s / BM_N);
}

/* The starting step of dop853.f (hinit), order 8. */
static double bm_initial_step(double t, const double *y, const double *f0, const double *P,
                              double rtol, double atol, double span)
{
    double y1[BM_N], f1[BM_N];
    double d0 = bm_norm(y, y, rtol, atol), d1 = bm_norm(f0, y, rtol, atol);
    double h0 = (d0 < 1e-5 || d1 < 1e-5) ? 1e-6 : 0.01 * d0 / d1;
    if (h0 > span) h0 = span;
    for (int i = 0; i < BM_N; ++i) y1[i] = y[i] + h0 * f0[i];
    chaplygin_rhs(t + h0, y1, P, f1);
    for (int i = 0; i < BM_N; ++i) f1[i] -= f0[i];
    double d2 = bm_norm(f1, y, rtol, atol) / h0;
    double dm = d1 > d2 ? d1 : d2;
    double h1 = dm <= 1e-15 ? fmax(1e-6, h0 * 1e-3) : chaplygin_pow(0.01 / dm, 1.0 / 8.0);
    double h = fmin(100.0 * h0, h1);
    return h < span ? h : span;
}

/* t0 + k (tau_hi + tau_lo), rounded once (up to the last bit of the small correction). */
{{BM_TIME}}

/* The DOP853 sums of a step, for one point (double) or for the lanes (bm_vec) alike: stage s's
 * increment a = sum_r A[s][r] K[r], the solution's b = sum_r B[r] K[r], and the error
 * estimates e5, e3; sums over r in the same order as variational.c, loops over the components
 * innermost (independent, vectorisable), zero coefficients skipped (adding 0 * K changes no
 * finite sum). The accumulators must be zero on entry. */
#define BM_STAGE_SUM(a, s, K)                                                                  \
    for (int r_ = 0; r_ < (s); ++r_) {                                                         \
        const double c_ = DOP_A[(s) * CV_STAGES + r_];                                         \
        if (c_ == 0.0) continue;                                                               \
        for (int i_ = 0; i_ < BM_N; ++i_) (a)[i_] += c_ * (K)[r_][i_];                         \
    }
#define BM_SOLUTION_SUM(b, K)                                                                  \
    for (int r_ = 0; r_ < CV_STAGES; ++r_) {                                                   \
        if (DOP_B[r_] == 0.0) continue;                                                        \
        for (int i_ = 0; i_ < BM_N; ++i_) (b)[i_] += DOP_B[r_] * (K)[r_][i_];                  \
    }
#define BM_ERROR_SUMS(e5, e3, K)                                                               \
    for (int r_ = 0; r_ <= CV_STAGES; ++r_) {                                                  \
        const double c5_ = DOP_E5[r_], c3_ = DOP_E3[r_];                                       \
        if (c5_ != 0.0)                                                                        \
            for (int i_ = 0; i_ < BM_N; ++i_) (e5)[i_] += c5_ * (K)[r_][i_];                   \
        if (c3_ != 0.0)                                                                        \
            for (int i_ = 0; i_ < BM_N; ++i_) (e3)[i_] += c3_ * (K)[r_][i_];                   \
    }

/* A step's error from its sums of squares n5, n3 over the BM_N components, INFINITY when the
 * new state yn is not finite. */
static double bm_lane_error(double n5, double n3, const double *yn, double hs)
{
    double err = 0.0;
    if (n5 > 0.0 || n3 > 0.0) err = hs * n5 / sqrt((n5 + 0.01 * n3) * BM_N);
    if (!isfinite(err) && !cv_finite(yn, BM_N)) err = INFINITY;
    return err;
}

/* The error of a step of size hs (dop853.f: err5 and err3 combined), INFINITY when the new
 * state is not finite. */
static double bm_step_error(const double *e5, const double *e3, const double *y,
                            const double *yn, double hs, double rtol, double atol)
{
    double n5 = 0.0, n3 = 0.0;
    for (int i = 0; i < BM_N; ++i) {
        const double sc = atol + rtol * fmax(fabs(y[i]), fabs(yn[i]));
        n5 += (e5[i] / sc) * (e5[i] / sc);
        n3 += (e3[i] / sc) * (e3[i] / sc);
    }
    return bm_lane_error(n5, n3, yn, hs);
}

/* The factor of the next step size after a step with error err (accepted when err <= 1). */
static double bm_step_factor(double err, int rejected_last)
{
    if (err > 1.0) {
        double fac = isfinite(err) ? 0.9 * chaplygin_pow(err, -1.0 / 8.0) : 0.2;
        return fac < 0.2 ? 0.2 : fac;
    }
    double fac = err == 0.0 ? 10.0 : 0.9 * chaplygin_pow(err, -1.0 / 8.0);
    if (fac > 10.0) fac = 10.0;
    if (rejected_last && fac > 1.0) fac = 1.0;
    return fac < 0.2 ? 0.2 : fac;
}

/* Advance one point from t to t1 (> t). K[0] holds f(t, y) on entry and f(t1, y1) on exit;
 * *h is the step size to try, updated. Returns 0 or a status. */
static int bm_advance(double *t_io, double t1, double *y, const double *P, double rtol,
                      double atol, long max_steps, double *h_io, double K[][BM_N],
                      double *stats)
{
    double ys[BM_N], yn[BM_N];
    double t = *t_io, h = *h_io;
    int rejected_last = 0;
    long steps = 0;
    while (t1 - t > 0.0) {
        if (++steps > max_steps) return 1;
        const double hmin = 10.0 * DBL_EPSILON * fmax(fabs(t), fabs(t1));
        if (h < hmin) return 2;
        double hs = h;
        int last = 0;
        if (hs >= t1 - t) {
            hs = t1 - t;
            last = 1;
        }
        for (int s = 1; s < CV_STAGES; ++s) {
            double a[BM_N] = {0.0};
            BM_STAGE_SUM(a, s, K)
            for (int i = 0; i < BM_N; ++i) ys[i] = y[i] + hs * a[i];
            chaplygin_rhs(t + DOP_C[s] * hs, ys, P, K[s]);
        }
        double b[BM_N] = {0.0}, e5[BM_N] = {0.0}, e3[BM_N] = {0.0};
        BM_SOLUTION_SUM(b, K)
        for (int i = 0; i < BM_N; ++i) yn[i] = y[i] + hs * b[i];
        const double tn = last ? t1 : t + hs;
        chaplygin_rhs(tn, yn, P, K[CV_STAGES]);
        stats[2] += CV_STAGES;
        BM_ERROR_SUMS(e5, e3, K)
        const double err = bm_step_error(e5, e3, y, yn, hs, rtol, atol);
        const double fac = bm_step_factor(err, rejected_last);
        if (err <= 1.0) {
            t = tn;
            for (int i = 0; i < BM_N; ++i) {
                y[i] = yn[i];
                K[0][i] = K[CV_STAGES][i];
            }
            stats[0] += 1;
            if (!last || fac < 1.0) h = hs * fac;
            rejected_last = 0;
            if (!cv_finite(y, BM_N)) return 3;
        } else {
            h = hs * fac;
            rejected_last = 1;
            stats[1] += 1;
        }
    }
    *t_io = t;
    *h_io = h;
    return 0;
}

void chaplygin_batch_map(long N, const double *Y0, const double *P, const double *T0,
                         const double *TAU_HI, const double *TAU_LO, long transient,
                         long n_record, double rtol, double atol, long max_steps, double *OUT,
                         double *STATS, int *STATUS)
{
    for (long j = 0; j < N; ++j) {
        const double *p = P + j * CHAPLYGIN_N_PARAM;
        double *out = OUT + j * n_record * BM_N;
        double *stats = STATS + 3 * j;
        double K[CV_STAGES + 1][BM_N];
        double y[BM_N];
        for (int i = 0; i < BM_N; ++i) y[i] = Y0[j * BM_N + i];
        for (long i = 0; i < n_record * BM_N; ++i) out[i] = NAN;
        stats[0] = stats[1] = stats[2] = 0.0;
        int status = cv_finite(y, BM_N) ? 0 : 3;
        double t = T0[j];
        double h = 0.0;
        if (!status) {
            chaplygin_rhs(t, y, p, K[0]);
            stats[2] += 1;
        }
        for (long k = 0; k < transient + n_record && !status; ++k) {
            if (k > 0) {
                const double t1 = bm_time(T0[j], k, TAU_HI[j], TAU_LO[j]);
                if (h == 0.0) {
                    h = bm_initial_step(t, y, K[0], p, rtol, atol, t1 - t);
                    stats[2] += 1;
                }
                status = bm_advance(&t, t1, y, p, rtol, atol, max_steps, &h, K, stats);
                if (status) break;
            }
            if (k >= transient)
                for (int i = 0; i < BM_N; ++i) out[(k - transient) * BM_N + i] = y[i];
        }
        if (status)
            for (long i = 0; i < n_record * BM_N; ++i) out[i] = NAN;
        STATUS[j] = status;
    }
}

#ifdef BM_VEC_RHS
#ifndef BM_W /* the widest registers: 8 doubles with AVX-512 (-march=native), else 4 */
#if defined(__AVX512F__)
#define BM_W 8
#else
#define BM_W 4
#endif
#endif
typedef double bm_vec __attribute__((vector_size(BM_W * sizeof(double))));

#define BM_LANEWISE(name)                                                                      \
    static inline bm_vec bm_v_##name(bm_vec x)                                                 \
    {                                                                                          \
        bm_vec r;                                                                              \
        for (int l = 0; l < BM_W; ++l) r[l] = name(x[l]);                                      \
        return r;                                                                              \
    }

/* chaplygin_sin and chaplygin_cos on all lanes at once: where every lane's |x| lies in
 * [2^-27, 2^20) (the Cody-Waite reduction of detmath.h), the scalar functions' operations
 * written on vectors — both reductions (|x| <= pi/4 or not) and all four kernels (sin or cos,
 * polynomial or table) computed and each lane's own one selected — so that every lane gets the
 * bits of the scalar function; otherwise lane by lane. */
typedef int64_t bm_ivec __attribute__((vector_size(BM_W * sizeof(int64_t))));

static inline bm_vec bm_select(bm_ivec mask, bm_vec a, bm_vec b) /* mask -1: a, 0: b */
{
    return (bm_vec)((mask & (bm_ivec)a) | (~mask & (bm_ivec)b));
}

static inline bm_vec bm_sincos_vec(bm_vec x, int odd)
{
    const bm_ivec magnitude = (bm_ivec){0} + INT64_C(0x7fffffffffffffff); /* all but the sign bit */
    const bm_vec ax = (bm_vec)((bm_ivec)x & magnitude);
    const bm_ivec ok = (ax >= 0x1p-27) & (ax < 0x1p20);
    int64_t all_ok = -1;
    for (int l = 0; l < BM_W; ++l) all_ok &= ok[l];
    if (!all_ok) {
        bm_vec r;
        for (int l = 0; l < BM_W; ++l) r[l] = odd ? chaplygin_cos(x[l]) : chaplygin_sin(x[l]);
        return r;
    }
    /* chaplygin_dm__rem_pio2 below 2^20, and the identity at |x| <= pi/4 */
    const bm_vec nd = (ax * chaplygin_dm_INV_PIO2 + CHAPLYGIN_DM_SHIFT) - CHAPLYGIN_DM_SHIFT;
    const bm_vec t1 = ax - nd * chaplygin_dm_CW_P1;
    const bm_vec p2 = -(nd * chaplygin_dm_CW_P2);
    const bm_vec t2 = t1 + p2, b2 = t2 - t1, e2 = (t1 - (t2 - b2)) + (p2 - b2);
    const bm_vec p3 = -(nd * chaplygin_dm_CW_P3);
    const bm_vec t3 = t2 + p3, b3 = t3 - t2, e3 = (t2 - (t3 - b3)) + (p3 - b3);
    const bm_vec lo = (e2 + e3) - nd * chaplygin_dm_CW_P4;
    const bm_vec h = t3 + lo, hl = lo - (h - t3);
    const bm_ivec small = ax <= chaplygin_dm_PI_O4;
    const bm_vec rh = bm_select(small, ax, h), rl = bm_select(small, (bm_vec){0}, hl);
    const bm_ivec n = (~small & (__builtin_convertvector(nd, bm_ivec) & 3)) + odd;
    /* the polynomial kernels (|rh| < 0.125) */
    const double *cs = chaplygin_dm_SIN_POLY, *cc = chaplygin_dm_COS_POLY;
    const bm_vec z = rh * rh, z2 = z * z;
    const bm_vec Ps = (cs[0] + z * cs[1]) + z2 * ((cs[2] + z * cs[3]) + z2 * cs[4]);
    const bm_vec sin_poly = rh + (rl + ((rh * z) * Ps - (0.5 * z) * rl));
    const bm_vec hz = 0.5 * z, w = 1.0 - hz, err = (1.0 - w) - hz;
    const bm_vec Qc = (cc[1] + z * cc[2]) + z2 * (cc[3] + z * cc[4]);
    const bm_vec cos_poly = w + (err + (z2 * Qc - rh * rl));
    /* the table kernels (chaplygin_dm__trig_split) */
    const bm_ivec neg = rh < 0.0;
    const bm_vec sg = bm_select(neg, (bm_vec){0} - 1.0, (bm_vec){0} + 1.0);
    const bm_vec xh = sg * rh, xl = sg * rl;
    const bm_vec id = (xh * 128.0 + CHAPLYGIN_DM_SHIFT) - CHAPLYGIN_DM_SHIFT;
    const bm_vec dh = xh - id * 0x1p-7, dz = dh * dh;
    const bm_vec sd = (dh * dz) * (chaplygin_dm_SIND_POLY[0] + dz * chaplygin_dm_SIND_POLY[1]);
    const bm_vec cd = dz * (chaplygin_dm_COSD_POLY[0] +
                            dz * (chaplygin_dm_COSD_POLY[1] + dz * chaplygin_dm_COSD_POLY[2]));
    const bm_ivec poly = (bm_vec)((bm_ivec)rh & magnitude) < 0.125;
    const bm_ivec index = ~poly & (__builtin_convertvector(id, bm_ivec) - 16);
    bm_vec S, Sl, C, Cl;
    for (int l = 0; l < BM_W; ++l) { /* the polynomial lanes read entry 0 (not used) */
        const long i = index[l];
        S[l] = chaplygin_dm_TRIG_S_HI[i];
        Sl[l] = chaplygin_dm_TRIG_S_LO[i];
        C[l] = chaplygin_dm_TRIG_C_HI[i];
        Cl[l] = chaplygin_dm_TRIG_C_LO[i];
    }
    const bm_vec bs = C * dh, ss = S + bs, es = bs - (ss - S);
    const bm_vec tail_s = Sl + (C * xl + Cl * dh) + (S * cd + C * sd);
    const bm_vec sin_table = sg * (ss + (es + tail_s));
    const bm_vec bc = -(S * dh), sc = C + bc, ec = bc - (sc - C);
    const bm_vec tail_c = Cl - (S * xl + Sl * dh) + (C * cd - S * sd);
    const bm_vec cos_table = sc + (ec + tail_c);
    const bm_vec sin_k = bm_select(poly, sin_poly, sin_table);
    const bm_vec cos_k = bm_select(poly, cos_poly, cos_table);
    bm_vec v = bm_select((n & 1) != 0, cos_k, sin_k);
    v = bm_select((n & 2) != 0, -v, v);
    return odd ? v : bm_select(x < 0.0, -v, v);
}

/* The sums of squares of every lane's step error over its first m components (bm_step_error's
 * and chaplygin_var_flow's estimate, their operations in their order; fmax and fabs as C's). */
static void bm_error_sums_vec(const bm_vec *a5, const bm_vec *a3, const bm_vec *z,
                              const bm_vec *zn, int m, double rtol, double atol, bm_vec *n5,
                              bm_vec *n3)
{
    const bm_ivec magnitude = (bm_ivec){0} + INT64_C(0x7fffffffffffffff);
    bm_vec s5 = {0}, s3 = {0};
    for (int i = 0; i < m; ++i) {
        const bm_vec a = (bm_vec)((bm_ivec)z[i] & magnitude);
        const bm_vec b = (bm_vec)((bm_ivec)zn[i] & magnitude);
        const bm_vec sc = atol + rtol * bm_select((a >= b) | (b != b), a, b); /* fmax */
        const bm_vec e5 = a5[i] / sc, e3 = a3[i] / sc;
        s5 += e5 * e5;
        s3 += e3 * e3;
    }
    *n5 = s5;
    *n3 = s3;
}

static inline bm_vec bm_v_chaplygin_sin(bm_vec x) { return bm_sincos_vec(x, 0); }
static inline bm_vec bm_v_chaplygin_cos(bm_vec x) { return bm_sincos_vec(x, 1); }

/* S, C = the lanes' sine and cosine of X[0 .. n-1], BM_W at a time (the last group padded
 * with its first argument): what the tests compare with chaplygin_sin and chaplygin_cos. */
int chaplygin_lanes_sincos(long n, const double *X, double *S, double *C)
{
    for (long j = 0; j < n; j += BM_W) {
        bm_vec x, s, c;
        for (int l = 0; l < BM_W; ++l) x[l] = X[j + l < n ? j + l : j];
        s = bm_v_chaplygin_sin(x);
        c = bm_v_chaplygin_cos(x);
        for (int l = 0; l < BM_W && j + l < n; ++l) {
            S[j + l] = s[l];
            C[j + l] = c[l];
        }
    }
    return BM_W;
}
BM_LANEWISE(chaplygin_exp)
BM_LANEWISE(chaplygin_log)
BM_LANEWISE(sqrt)
BM_LANEWISE(fabs)

static void bm_rhs_vec(bm_vec T, const bm_vec *restrict Y, const bm_vec *restrict P,
                       bm_vec *restrict OUT);

typedef struct {
    long point;   /* index in the batch, -1: idle */
    long k;       /* sampling times reached */
    double t, t1, h;
    int rejected_last;
    long steps;   /* steps in the current period */
} bm_lane;

/* Put point j into lane l (state, parameters, f(t0, y0)); record its first point. Returns 0,
 * or the status of a point that fails at once. */
static int bm_load(long j, int l, bm_lane *lane, bm_vec *y, bm_vec *P, bm_vec K[][BM_N],
                   const double *Y0, const double *PP, const double *T0, long transient,
                   double *OUT, long n_record, double *STATS)
{
    double yj[BM_N], f[BM_N];
    const double *p = PP + j * CHAPLYGIN_N_PARAM;
    double *out = OUT + j * n_record * BM_N;
    for (long i = 0; i < n_record * BM_N; ++i) out[i] = NAN;
    STATS[3 * j] = STATS[3 * j + 1] = STATS[3 * j + 2] = 0.0;
    for (int i = 0; i < BM_N; ++i) yj[i] = Y0[j * BM_N + i];
    lane->point = j;
    lane->k = 0;
    lane->t = lane->t1 = T0[j];
    lane->h = 0.0;
    lane->rejected_last = 0;
    lane->steps = 0;
    if (!cv_finite(yj, BM_N)) return 3;
    chaplygin_rhs(lane->t, yj, p, f);
    STATS[3 * j + 2] += 1;
    for (int i = 0; i < BM_N; ++i) {
        y[i][l] = yj[i];
        K[0][i][l] = f[i];
    }
    for (int i = 0; i < CHAPLYGIN_N_PARAM; ++i) P[i][l] = p[i];
    if (transient == 0)
        for (int i = 0; i < BM_N; ++i) out[i] = yj[i];
    return 0;
}

void chaplygin_batch_map_lockstep(long N, const double *Y0, const double *PP, const double *T0,
                                  const double *TAU_HI, const double *TAU_LO, long transient,
                                  long n_record, double rtol, double atol, long max_steps,
                                  double *OUT, double *STATS, int *STATUS)
{
    const long last_k = transient + n_record - 1;
    bm_vec y[BM_N], ys[BM_N], yn[BM_N], P[CHAPLYGIN_N_PARAM], K[CV_STAGES + 1][BM_N];
    bm_lane lane[BM_W];
    long next = 0;
    int active = 0;
    for (int i = 0; i < BM_N; ++i) y[i] = (bm_vec){0};
    for (int i = 0; i < CHAPLYGIN_N_PARAM; ++i) P[i] = (bm_vec){0};
    for (int r = 0; r <= CV_STAGES; ++r)
        for (int i = 0; i < BM_N; ++i) K[r][i] = (bm_vec){0};
    /* fill a lane with the next point that needs work; idle lanes keep their (finite) values */
    #define BM_REFILL(l)                                                                       \
        do {                                                                                   \
            lane[l].point = -1;                                                                \
            while (next < N) {                                                                 \
                long j_ = next++;                                                              \
                int st_ = bm_load(j_, l, &lane[l], y, P, K, Y0, PP, T0, transient, OUT,        \
                                  n_record, STATS);                                            \
                STATUS[j_] = st_;                                                              \
                if (st_ == 0 && last_k > 0) break;                                             \
                lane[l].point = -1;                                                            \
            }                                                                                  \
        } while (0)
    for (int l = 0; l < BM_W; ++l) {
        BM_REFILL(l);
        if (lane[l].point >= 0) ++active;
    }
    if (active > 0) { /* idle lanes copy a working lane so that they compute finite numbers */
        int w = 0;
        while (lane[w].point < 0) ++w;
        for (int l = 0; l < BM_W; ++l) {
            if (lane[l].point >= 0) continue;
            for (int i = 0; i < BM_N; ++i) {
                y[i][l] = y[i][w];
                K[0][i][l] = K[0][i][w];
            }
            for (int i = 0; i < CHAPLYGIN_N_PARAM; ++i) P[i][l] = P[i][w];
            lane[l].t = lane[w].t;
        }
    }
    while (active > 0) {
        bm_vec hs = {0}, tv = {0};
        int last[BM_W];
        for (int l = 0; l < BM_W; ++l) {
            bm_lane *L = &lane[l];
            tv[l] = L->t;
            last[l] = 0;
            if (L->point < 0) continue;
            const long j = L->point;
            if (L->steps == 0 && L->t1 <= L->t) /* a new period: its end */
                L->t1 = bm_time(T0[j], L->k + 1, TAU_HI[j], TAU_LO[j]);
            if (L->h == 0.0) {
                double yl[BM_N], fl[BM_N], pl[CHAPLYGIN_N_PARAM];
                for (int i = 0; i < BM_N; ++i) {
                    yl[i] = y[i][l];
                    fl[i] = K[0][i][l];
                }
                for (int i = 0; i < CHAPLYGIN_N_PARAM; ++i) pl[i] = P[i][l];
                L->h = bm_initial_step(L->t, yl, fl, pl, rtol, atol, L->t1 - L->t);
                STATS[3 * j + 2] += 1;
            }
            int status = 0;
            if (++L->steps > max_steps) status = 1;
            else if (L->h < 10.0 * DBL_EPSILON * fmax(fabs(L->t), fabs(L->t1))) status = 2;
            if (status) {
                STATUS[j] = status;
                for (long i = 0; i < n_record * BM_N; ++i) OUT[j * n_record * BM_N + i] = NAN;
                BM_REFILL(l);
                if (L->point < 0) { --active; continue; }
                --l; /* the new point starts in this lane: prepare its step */
                continue;
            }
            double h = L->h;
            if (h >= L->t1 - L->t) {
                h = L->t1 - L->t;
                last[l] = 1;
            }
            hs[l] = h;
        }
        if (active == 0) break;
        for (int s = 1; s < CV_STAGES; ++s) {
            bm_vec a[BM_N];
            for (int i = 0; i < BM_N; ++i) a[i] = (bm_vec){0};
            BM_STAGE_SUM(a, s, K)
            for (int i = 0; i < BM_N; ++i) ys[i] = y[i] + hs * a[i];
            bm_rhs_vec(tv + DOP_C[s] * hs, ys, P, K[s]);
        }
        bm_vec b[BM_N], e5[BM_N], e3[BM_N], tn = tv + hs;
        for (int i = 0; i < BM_N; ++i) b[i] = e5[i] = e3[i] = (bm_vec){0};
        BM_SOLUTION_SUM(b, K)
        for (int i = 0; i < BM_N; ++i) yn[i] = y[i] + hs * b[i];
        for (int l = 0; l < BM_W; ++l)
            if (last[l]) tn[l] = lane[l].t1;
        bm_rhs_vec(tn, yn, P, K[CV_STAGES]);
        BM_ERROR_SUMS(e5, e3, K)
        bm_vec n5, n3;
        bm_error_sums_vec(e5, e3, y, yn, BM_N, rtol, atol, &n5, &n3);
        for (int l = 0; l < BM_W; ++l) {
            bm_lane *L = &lane[l];
            if (L->point < 0) continue;
            const long j = L->point;
            double *stats = STATS + 3 * j;
            stats[2] += CV_STAGES;
            double ynl[BM_N];
            for (int i = 0; i < BM_N; ++i) ynl[i] = yn[i][l];
            const double h = hs[l];
            const double err = bm_lane_error(n5[l], n3[l], ynl, h);
            const double fac = bm_step_factor(err, L->rejected_last);
            if (err > 1.0) {
                L->h = h * fac;
                L->rejected_last = 1;
                stats[1] += 1;
                continue;
            }
            L->t = tn[l];
            for (int i = 0; i < BM_N; ++i) {
                y[i][l] = ynl[i];
                K[0][i][l] = K[CV_STAGES][i][l];
            }
            stats[0] += 1;
            if (!last[l] || fac < 1.0) L->h = h * fac;
            L->rejected_last = 0;
            int status = cv_finite(ynl, BM_N) ? 0 : 3;
            if (!status && last[l]) { /* reached t_k */
                L->k += 1;
                L->steps = 0;
                L->rejected_last = 0;
                if (L->k >= transient) {
                    double *out = OUT + (j * n_record + (L->k - transient)) * BM_N;
                    for (int i = 0; i < BM_N; ++i) out[i] = ynl[i];
                }
                if (L->k < last_k) continue;
            } else if (!status) {
                continue;
            }
            STATUS[j] = status;
            if (status)
                for (long i = 0; i < n_record * BM_N; ++i) OUT[j * n_record * BM_N + i] = NAN;
            BM_REFILL(l);
            if (L->point < 0) --active;
        }
    }
    #undef BM_REFILL
}
#endif
