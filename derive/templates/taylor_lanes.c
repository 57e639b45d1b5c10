/* The Taylor integrator of many orbits, TL_W at a time in the lanes of a GNU C vector
 * (issue 26; heyoka calls this its batch mode). chaplygin_taylor_lanes_width() is TL_W.
 *
 * Appended to a model's emitted Taylor C source (generated/<model>_taylor.c, the double
 * build), whose order and step control (taylor_control_of, inf_norm) and compensated dense
 * output (taylor_eval_compensated) it calls; the coefficients of the lanes
 * (taylor_coefficients_lanes, the loop over the orders, and the functions written out for the
 * run's orders that TL_COEFFICIENTS picks from) are printed from the model's Taylor program
 * (chaplygin.derive.emit.taylor_lanes) where the placeholder below stands
 * (chaplygin.derive.emit.c_sources.taylor_batch_source).
 *
 * Every lane is one orbit with its own time, state, compensation, parameters, order, step
 * and end time; the recurrences (the bulk of the work) run on all lanes at once, each lane
 * with the IEEE operations of chaplygin_taylor_run in the same order (no contraction: the
 * build has -ffp-contract=off; functions lane by lane through detmath); the step control runs
 * lane by lane with chaplygin_taylor_run's own code, and the state update (Horner and the
 * compensated sum of taylor_eval_compensated) on the vectors when the stepping lanes share
 * the order, else lane by lane. So every orbit's
 * outputs, final state, time reached and counters are, bit for bit, those of one
 * chaplygin_taylor_run call on it, whatever TL_W, the other lanes or the chunking of the
 * orbits over calls and threads. Lanes that want different orders (one under absolute, one
 * under relative control) share the highest: the coefficient of order k does not depend on
 * the order the recurrences run to, and each lane reads its own p + 1 coefficients. A lane
 * whose orbit ends (reached, failed, out of steps) takes the next orbit of the call; idle
 * lanes repeat a working lane's numbers (finite, discarded).
 *
 * chaplygin_taylor_run_lanes(N, T01, Y0, P, CTRL, fixed_order, n_eval, T_EVAL, eval_stride,
 *                            Y_EVAL, Y_END, T_REACHED, max_steps, STATS, STATUS)
 *   T01 N x 2, Y0 N x n_state, P N x n_param: each orbit's span, start and parameters
 *   CTRL, fixed_order, max_steps: chaplygin_taylor_run's, common to the orbits
 *   T_EVAL: orbit j's n_eval output times at T_EVAL + j eval_stride (0: shared)
 *   Y_EVAL N x n_eval x n_state, Y_END N x n_state, T_REACHED N, STATS N x 4 (steps, highest
 *   order, lowest order, outputs written): chaplygin_taylor_run's, per orbit
 *   STATUS N: on entry, orbits with a nonzero status are skipped (left as they are); on exit
 *   chaplygin_taylor_run's return value of each orbit run (0, -1, -2, -3; -4 no memory)
 * Returns 0, or -4 when the workspace could not be allocated.
 */
#include <stdint.h>
#include <stdlib.h>

#ifndef TL_W /* the widest registers: 8 doubles with AVX-512 (-march=native), else 4 */
#if defined(__AVX512F__)
#define TL_W 8
#else
#define TL_W 4
#endif
#endif
typedef double tl_vec __attribute__((vector_size(TL_W * sizeof(double))));

static inline tl_vec tl_splat(double x)
{
    tl_vec z;
    for (int l = 0; l < TL_W; ++l) z[l] = x;
    return z;
}
static inline tl_vec tl_zero(void) { return tl_splat(0.0); }
static inline tl_vec tl_twice(tl_vec s) { return s + s; } /* 2 s as the loop writes it */

/* The recurrences of taylor.c (tc_mul .. tc_exp) on the lanes: the same operations in the
 * same order, lane by lane. */
static inline tl_vec tl_mul(const tl_vec *restrict a, const tl_vec *restrict b, int k)
{
    tl_vec last = a[0] * b[k] + a[k] * b[0];
    if (k < 2) return last;
    tl_vec s = a[1] * b[k - 1];
    for (int j = 2; j < k; ++j) s = s + a[j] * b[k - j];
    return s + last;
}

static inline tl_vec tl_sq(const tl_vec *restrict a, int k)
{
    tl_vec s = a[0] * a[k];
    if (k >= 3) {
        tl_vec o = a[1] * a[k - 1];
        for (int j = 2; j < (k + 1) / 2; ++j) o = o + a[j] * a[k - j];
        s = o + s;
    }
    s = s + s;
    if (k % 2 == 0) s = s + a[k / 2] * a[k / 2];
    return s;
}

static inline tl_vec tl_div(tl_vec ak, const tl_vec *restrict b, const tl_vec *restrict c,
                            tl_vec r, int k)
{
    tl_vec last = ak - b[k] * c[0];
    if (k < 2) return last * r;
    tl_vec s = b[1] * c[k - 1];
    for (int j = 2; j < k; ++j) s = s + b[j] * c[k - j];
    return (last - s) * r;
}

static inline tl_vec tl_sqrt(const tl_vec *restrict a, const tl_vec *restrict c, int k)
{
    tl_vec s = a[k];
    for (int j = 1; j < k; ++j) s = s - c[j] * c[k - j];
    return s / (2.0 * c[0]);
}

static inline tl_vec tl_pow(const tl_vec *restrict a, const tl_vec *restrict c, int p, int q,
                            int k)
{
    tl_vec s = tl_zero();
    for (int j = 0; j < k; ++j) s = s + ((double)(p * (k - j) - q * j) * a[k - j]) * c[j];
    return s / (((double)q * (double)k) * a[0]);
}

static inline tl_vec tl_exp(const tl_vec *restrict a, const tl_vec *restrict c, int k)
{
    tl_vec s = tl_zero();
    for (int j = 1; j <= k; ++j) s = s + ((double)j * a[j]) * c[k - j];
    return s * (1.0 / (double)k);
}

{{COEFFICIENTS_LANES}}

#ifndef TL_COEFFICIENTS /* no written-out orders: the loop */
#define TL_COEFFICIENTS taylor_coefficients_lanes
#endif

/* One orbit in a lane: chaplygin_taylor_run's locals. */
typedef struct {
    long point; /* the orbit, -1: idle */
    double t, t_end, dir, xn, t_new;
    long steps, j;
    int pmax, pmin, p, absolute, status;
    double y[CHAPLYGIN_TAYLOR_N_STATE], ylo[CHAPLYGIN_TAYLOR_N_STATE];
} tl_lane;

/* The arguments of a call, for the lane functions. */
typedef struct {
    const double *T01, *Y0, *P, *T_EVAL;
    long n_eval, eval_stride, max_steps;
    double *Y_EVAL, *Y_END, *T_REACHED;
    long *STATS;
    int *STATUS;
} tl_call;

/* Start orbit j in lane L: chaplygin_taylor_run's set-up and its outputs at t0. Returns
 * whether the orbit needs a step. */
static int tl_load(tl_lane *L, long j, const tl_call *a)
{
    const int n = CHAPLYGIN_TAYLOR_N_STATE;
    const double *t_eval = a->T_EVAL + j * a->eval_stride;
    double *y_eval = a->Y_EVAL + j * a->n_eval * n;
    L->point = j;
    L->t = a->T01[2 * j];
    L->t_end = a->T01[2 * j + 1];
    L->dir = L->t_end < L->t ? -1 : 1;
    for (int i = 0; i < n; ++i) {
        L->y[i] = a->Y0[j * n + i];
        L->ylo[i] = 0;
    }
    L->steps = L->j = 0;
    L->pmax = 0;
    L->pmin = CHAPLYGIN_TAYLOR_MAX_ORDER;
    L->status = 0;
    while (L->j < a->n_eval && L->dir * (t_eval[L->j] - L->t) <= 0) {
        for (int i = 0; i < n; ++i) y_eval[L->j * n + i] = L->y[i] + L->ylo[i];
        ++L->j;
    }
    return 0 < L->dir * (L->t_end - L->t);
}

/* Orbit of lane L done: its final state, time, counters and status. */
static void tl_finish(const tl_lane *L, const tl_call *a)
{
    const int n = CHAPLYGIN_TAYLOR_N_STATE;
    const long j = L->point;
    for (int i = 0; i < n; ++i) a->Y_END[j * n + i] = L->y[i];
    a->T_REACHED[j] = L->t;
    a->STATS[4 * j] = L->steps;
    a->STATS[4 * j + 1] = L->pmax;
    a->STATS[4 * j + 2] = L->steps ? L->pmin : 0;
    a->STATS[4 * j + 3] = L->j;
    a->STATUS[j] = L->status;
}

/* The next orbit that needs a step into lane L (orbits done at once are finished), or idle. */
static void tl_next(tl_lane *L, long *next, long N, const tl_call *a)
{
    L->point = -1;
    while (*next < N) {
        const long j = (*next)++;
        if (a->STATUS[j]) continue;
        if (tl_load(L, j, a)) return;
        tl_finish(L, a);
        L->point = -1;
    }
}

/* Before the coefficients: the step limit (0: the orbit stops), the order of the step. */
static int tl_prepare(tl_lane *L, const taylor_control *c, long max_steps)
{
    if (L->steps >= max_steps) {
        L->status = -2;
        return 0;
    }
    double xn = 0;
    for (int i = 0; i < CHAPLYGIN_TAYLOR_N_STATE; ++i)
        if (xn < fabs(L->y[i])) xn = fabs(L->y[i]);
    L->xn = xn;
    L->absolute = c->rtol * xn <= c->atol;
    L->p = c->order[L->absolute];
    return 1;
}

/* inf_norm of lane l's state coefficients of order k (XV of row length S). */
static double tl_norm(const tl_vec *restrict XV, int S, int k, int l)
{
    double m = 0;
    for (int i = 0; i < CHAPLYGIN_TAYLOR_N_STATE; ++i) {
        const double v = fabs(XV[i * S + k][l]);
        if (m < v) m = v;
    }
    return m;
}

/* taylor_step_size after the coefficients (lane l of XV, row length S). */
static double tl_step_size(const tl_lane *L, const taylor_control *c, const tl_vec *XV, int S,
                           int l)
{
    const int p = L->p;
    const double remaining = L->t_end - L->t;
    const double dir = remaining < 0 ? -1 : 1;
    double h;
    if (0 < c->fixed_h) {
        h = c->fixed_h;
    } else {
        double e = INFINITY;
        const double log_scale = L->absolute ? 0.0 : R_LOG_D(L->xn);
        const double n1 = tl_norm(XV, S, p - 1, l), n2 = tl_norm(XV, S, p, l);
        if (0 < n1) {
            double r = (log_scale - R_LOG_D(n1)) / (p - 1);
            if (r < e) e = r;
        }
        if (0 < n2) {
            double r = (log_scale - R_LOG_D(n2)) / p;
            if (r < e) e = r;
        }
        double rho = chaplygin_exp(e);
        if (isinf(rho)) h = fabs(remaining);
        else h = rho * c->safety[L->absolute];
    }
    if (fabs(remaining) <= h) return remaining;
    return dir * h;
}

/* Lane l's state coefficients (orders 0 .. p) in X, row length p + 1, as taylor.c has them. */
static void tl_extract(const tl_vec *restrict XV, int S, int p, int l, double *restrict X)
{
    for (int i = 0; i < CHAPLYGIN_TAYLOR_N_STATE; ++i)
        for (int k = 0; k <= p; ++k) X[i * (p + 1) + k] = XV[i * S + k][l];
}

/* chaplygin_taylor_run's step of lane l up to the state update: the step size (0 when the
 * step underflows: the orbit stops), the orders, the outputs inside the step. */
static double tl_begin_step(tl_lane *L, const taylor_control *c, const tl_vec *XV, int S, int l,
                            double *X, const tl_call *a)
{
    const int n = CHAPLYGIN_TAYLOR_N_STATE, p = L->p;
    const double *t_eval = a->T_EVAL + L->point * a->eval_stride;
    double *y_eval = a->Y_EVAL + L->point * a->n_eval * n;
    const double h = tl_step_size(L, c, XV, S, l);
    if (h == 0 || L->t + h == L->t) {
        L->status = -3;
        return 0;
    }
    if (p > L->pmax) L->pmax = p;
    if (p < L->pmin) L->pmin = p;
    const int last = h == L->t_end - L->t;
    L->t_new = last ? L->t_end : L->t + h;
    if (L->j < a->n_eval && L->dir * (t_eval[L->j] - L->t_new) <= 0) {
        tl_extract(XV, S, p, l, X);
        while (L->j < a->n_eval && L->dir * (t_eval[L->j] - L->t_new) <= 0) {
            taylor_eval_compensated(X, p, t_eval[L->j] - L->t, L->ylo, y_eval + L->j * n, NULL);
            ++L->j;
        }
    }
    return h;
}

/* The state update of every stepping lane (step hv[l] != 0): taylor_eval_compensated's
 * operations, on the vectors when the lanes share the order p (else lane by lane). */
static void tl_update(tl_lane *lane, const tl_vec *XV, int S, int p, tl_vec hv, double *X)
{
    const int n = CHAPLYGIN_TAYLOR_N_STATE;
    if (p < 0) {
        for (int l = 0; l < TL_W; ++l) {
            tl_lane *L = &lane[l];
            if (L->point < 0 || hv[l] == 0) continue;
            double ylo_new[CHAPLYGIN_TAYLOR_N_STATE];
            tl_extract(XV, S, L->p, l, X);
            taylor_eval_compensated(X, L->p, hv[l], L->ylo, L->y, ylo_new);
            for (int i = 0; i < n; ++i) L->ylo[i] = ylo_new[i];
        }
        return;
    }
    for (int i = 0; i < n; ++i) {
        const tl_vec *c = XV + i * S;
        tl_vec lo;
        for (int l = 0; l < TL_W; ++l) lo[l] = lane[l].point >= 0 ? lane[l].ylo[i] : 0.0;
        tl_vec v = c[p];
        for (int k = p - 1; k >= 1; --k) v = v * hv + c[k];
        const tl_vec d = v * hv + lo;
        const tl_vec y = c[0] + d;
        const tl_vec bb = y - c[0];
        lo = (c[0] - (y - bb)) + (d - bb);
        for (int l = 0; l < TL_W; ++l) {
            if (lane[l].point < 0 || hv[l] == 0) continue;
            lane[l].y[i] = y[l];
            lane[l].ylo[i] = lo[l];
        }
    }
}

/* After the update: chaplygin_taylor_run's check and time. Returns whether the orbit goes on. */
static int tl_end_step(tl_lane *L)
{
    ++L->steps;
    for (int i = 0; i < CHAPLYGIN_TAYLOR_N_STATE; ++i)
        if (!isfinite(L->y[i])) L->status = -1;
    L->t = L->t_new;
    if (L->status) return 0;
    return 0 < L->dir * (L->t_end - L->t);
}

/* The lanes' time, state and parameters (an idle lane: those of lane w). */
static void tl_pack(const tl_lane *lane, int w, const double *P, tl_vec *T, tl_vec *Y, tl_vec *PV)
{
    for (int l = 0; l < TL_W; ++l) {
        const tl_lane *L = &lane[lane[l].point >= 0 ? l : w];
        (*T)[l] = L->t;
        for (int i = 0; i < CHAPLYGIN_TAYLOR_N_STATE; ++i) Y[i][l] = L->y[i];
        for (int i = 0; i < CHAPLYGIN_TAYLOR_N_PARAM; ++i)
            PV[i][l] = P[L->point * CHAPLYGIN_TAYLOR_N_PARAM + i];
    }
}

int chaplygin_taylor_lanes_width(void) { return TL_W; }

int chaplygin_taylor_run_lanes(long N, const double *T01, const double *Y0, const double *P,
                               const double *CTRL, int fixed_order, long n_eval,
                               const double *T_EVAL, long eval_stride, double *Y_EVAL,
                               double *Y_END, double *T_REACHED, long max_steps, long *STATS,
                               int *STATUS)
{
    const tl_call a = {T01, Y0, P, T_EVAL, n_eval, eval_stride, max_steps, Y_EVAL, Y_END,
                       T_REACHED, STATS, STATUS};
    /* the workspace aligned for the vector type (malloc's alignment may be less) */
    char *block = malloc(sizeof(tl_vec) * ((CHAPLYGIN_TAYLOR_MAX_ORDER + 1)
                                           * CHAPLYGIN_TAYLOR_N_NODES + 1));
    tl_vec *XV = (tl_vec *)(block + (sizeof(tl_vec) - (uintptr_t)block % sizeof(tl_vec))
                                        % sizeof(tl_vec));
    if (block == NULL) {
        for (long j = 0; j < N; ++j)
            if (!STATUS[j]) STATUS[j] = -4;
        return -4;
    }
    const taylor_control c = taylor_control_of(CTRL, fixed_order);
    double X[(CHAPLYGIN_TAYLOR_MAX_ORDER + 1) * CHAPLYGIN_TAYLOR_N_STATE];
    tl_vec T, Y[CHAPLYGIN_TAYLOR_N_STATE], PV[CHAPLYGIN_TAYLOR_N_PARAM + 1];
    tl_lane lane[TL_W];
    long next = 0;
    for (int l = 0; l < TL_W; ++l) tl_next(&lane[l], &next, N, &a);
    for (;;) {
        int order = 0, w = -1;
        for (int l = 0; l < TL_W; ++l) {
            tl_lane *L = &lane[l];
            while (L->point >= 0 && !tl_prepare(L, &c, max_steps)) {
                tl_finish(L, &a);
                tl_next(L, &next, N, &a);
            }
            if (L->point < 0) continue;
            if (w < 0) w = l;
            if (L->p > order) order = L->p;
        }
        if (w < 0) break;
        tl_pack(lane, w, P, &T, Y, PV);
        TL_COEFFICIENTS(order, T, Y, PV, XV);
        tl_vec hv = tl_zero();
        int common = -1; /* the order every stepping lane has, or -1 */
        for (int l = 0; l < TL_W; ++l) {
            tl_lane *L = &lane[l];
            if (L->point < 0) continue;
            hv[l] = tl_begin_step(L, &c, XV, order + 1, l, X, &a);
            if (hv[l] == 0) continue;
            common = common == -1 || common == L->p ? L->p : -2;
        }
        tl_update(lane, XV, order + 1, common < 0 ? -1 : common, hv, X);
        for (int l = 0; l < TL_W; ++l) {
            tl_lane *L = &lane[l];
            if (L->point < 0) continue;
            if (hv[l] != 0 && tl_end_step(L)) continue;
            tl_finish(L, &a);
            tl_next(L, &next, N, &a);
        }
    }
    free(block);
    return 0;
}
