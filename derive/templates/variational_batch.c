/* chaplygin.numerics.dynamics.lyapunov: Benettin's loop for many points in one call, in C.
 *
 * Appended after templates/batch_map.c (chaplygin.derive.emit.c_sources.batch_source), so that
 * the model's C (chaplygin_rhs, chaplygin_rhs_jac, chaplygin_integrals), the DOP853 of
 * templates/variational.c (cv_f, cv_initial_step, cv_normal_basis, chaplygin_var_renormalised)
 * and the vector type of batch_map.c (bm_vec, BM_W, the lane-wise functions) are defined.
 *
 * chaplygin_var_renormalised_many(N, k, Z0, P, T0, TAU, n_intervals, rtol, atol, project,
 *                                 max_steps, Z, LOGS, DIVS, STATS, STATUS)
 *   Z0, Z  N x (n + n k + 1)  the augmented states (y, V, q) of templates/variational.c, at
 *                             the start and at the end (as far as the point got)
 *   P      N x n_param        parameters (row per point)
 *   T0, TAU N                 start time and interval of each point
 *   LOGS   N x n_intervals x k  log R_jj of each interval's QR;  DIVS N x n_intervals
 *   STATS  N x 4              accepted, rejected steps, evaluations, last step size
 *   STATUS N                  0 done, else the status of chaplygin_var_renormalised
 * Point j is exactly chaplygin_var_renormalised(T0[j], TAU[j], n_intervals, ...) on its own
 * row, with its own statistics starting at zero (no step size carried between points).
 *
 * chaplygin_var_renormalised_lockstep(same arguments): the same computation, BM_W points at a
 * time in the lanes of GCC vector types (BM_VEC_JAC defined: bm_rhs_jac_vec of
 * generated/<model>_lanes.c is the emitted chaplygin_rhs_jac in lanes). Every lane takes its own
 * steps; the stage sums, the right-hand side, the Jacobian and the tangent vectors' products
 * run on all lanes at once, each lane with the IEEE operations of chaplygin_var_flow in the same
 * order (no contraction, detmath's sine and cosine on vectors with the scalar bits, other
 * functions lane by lane; stage sums without the zero coefficients of the
 * tableau, which change no finite sum). At the end of an interval a lane's point leaves the
 * lanes for the projection and the QR (the scalar code of chaplygin_var_renormalised), and the
 * next interval starts as chaplygin_var_flow starts one: f evaluated afresh at the new tangent
 * vectors, the step size of the last step kept, the step count and the rejection flag reset.
 * The results are bit-identical to chaplygin_var_renormalised_many.
 */

void chaplygin_var_renormalised_many(long N, int k, const double *Z0, const double *P,
                                     const double *T0, const double *TAU, long n_intervals,
                                     double rtol, double atol, int project, long max_steps,
                                     double *Z, double *LOGS, double *DIVS, double *STATS,
                                     int *STATUS)
{
    const int mz = CV_N + CV_N * k + 1;
    for (long j = 0; j < N; ++j) {
        double *z = Z + j * mz, *stats = STATS + 4 * j;
        for (int i = 0; i < mz; ++i) z[i] = Z0[j * mz + i];
        stats[0] = stats[1] = stats[2] = stats[3] = 0.0;
        STATUS[j] = chaplygin_var_renormalised(
            T0[j], TAU[j], n_intervals, z, k, P + j * CHAPLYGIN_N_PARAM, rtol, atol, project,
            max_steps, LOGS + j * n_intervals * k, DIVS + j * n_intervals, stats);
    }
}

#if defined(BM_VEC_RHS) && defined(BM_VEC_JAC)
static void bm_rhs_jac_vec(bm_vec T, const bm_vec *restrict Y, const bm_vec *restrict P,
                           bm_vec *restrict OUT);

/* cv_f in the lanes: f, J V and tr J, the sums in cv_f's order */
static void cvl_f(bm_vec t, const bm_vec *z, int k, const bm_vec *P, bm_vec *out)
{
    bm_vec FJ[CV_N + CV_N * CV_N];
    const bm_vec *J = FJ + CV_N;
    const bm_vec *V = z + CV_N;
    bm_vec *dV = out + CV_N;
    bm_rhs_jac_vec(t, z, P, FJ);
    bm_vec tr = {0};
    for (int i = 0; i < CV_N; ++i) {
        out[i] = FJ[i];
        tr += J[i * CV_N + i];
        for (int j = 0; j < k; ++j) {
            bm_vec s = {0};
            for (int l = 0; l < CV_N; ++l) s += J[i * CV_N + l] * V[l * k + j];
            dV[i * k + j] = s;
        }
    }
    out[CV_N + CV_N * k] = tr;
}

/* One lane's error from its sums, INFINITY when the new state is not finite. */
static double cvl_step_error(double n5, double n3, const double *zn, int m, int mz, double hs)
{
    double err = 0.0;
    if (n5 > 0.0 || n3 > 0.0) err = hs * n5 / sqrt((n5 + 0.01 * n3) * m);
    if (!isfinite(err) && !cv_finite(zn, mz)) err = INFINITY;
    return err;
}

typedef struct {
    long point;  /* index in the batch, -1: idle */
    long it;     /* intervals done */
    double t, t1, h;
    int rejected_last;
    long steps;  /* steps in the current interval */
} cvl_lane;

/* Lane l's augmented state and parameters, as doubles */
static void cvl_get(const bm_vec *z, int mz, int l, double *zl)
{
    for (int i = 0; i < mz; ++i) zl[i] = z[i][l];
}

/* Start an interval of lane l (its state in zl): q = 0, f afresh, the step size kept (or the
 * starting step of a point's first interval), as chaplygin_var_flow. */
static void cvl_start(cvl_lane *L, int l, double *zl, int k, const double *p, double tau,
                      double t0, double rtol, double atol, bm_vec *z, bm_vec K0[],
                      double *stats)
{
    const int mz = CV_N + CV_N * k + 1;
    double f[CV_ZMAX];
    L->t = t0 + (double)L->it * tau;
    L->t1 = t0 + (double)(L->it + 1) * tau;
    zl[mz - 1] = 0.0;
    cv_f(L->t, zl, k, p, f);
    stats[2] += 1;
    if (!(L->h > 0.0) || !isfinite(L->h)) {
        L->h = cv_initial_step(L->t, zl, f, k, p, rtol, atol, fabs(L->t1 - L->t));
        stats[2] += 1;
    }
    L->steps = 0;
    L->rejected_last = 0;
    for (int i = 0; i < mz; ++i) {
        z[i][l] = zl[i];
        K0[i][l] = f[i];
    }
}

void chaplygin_var_renormalised_lockstep(long N, int k, const double *Z0, const double *PP,
                                         const double *T0, const double *TAU, long n_intervals,
                                         double rtol, double atol, int project, long max_steps,
                                         double *Z, double *LOGS, double *DIVS, double *STATS,
                                         int *STATUS)
{
    const int m = CV_N + CV_N * k, mz = m + 1;
    bm_vec z[CV_ZMAX], zs[CV_ZMAX], zn[CV_ZMAX], P[CHAPLYGIN_N_PARAM];
    bm_vec K[CV_STAGES + 1][CV_ZMAX];
    cvl_lane lane[BM_W];
    double zl[CV_ZMAX];
    long next = 0;
    int active = 0;
    for (int i = 0; i < CV_ZMAX; ++i) z[i] = zs[i] = zn[i] = (bm_vec){0};
    for (int i = 0; i < CHAPLYGIN_N_PARAM; ++i) P[i] = (bm_vec){0};
    for (int r = 0; r <= CV_STAGES; ++r)
        for (int i = 0; i < CV_ZMAX; ++i) K[r][i] = (bm_vec){0};
    /* fill lane l with the next point (none left: the lane idles, keeping finite values) */
    #define CVL_REFILL(l)                                                                      \
        do {                                                                                   \
            lane[l].point = -1;                                                                \
            while (next < N) {                                                                 \
                long j_ = next++;                                                              \
                double *st_ = STATS + 4 * j_;                                                  \
                st_[0] = st_[1] = st_[2] = st_[3] = 0.0;                                       \
                for (int i_ = 0; i_ < mz; ++i_) zl[i_] = Z[j_ * mz + i_] = Z0[j_ * mz + i_];   \
                STATUS[j_] = 0;                                                                \
                if (n_intervals <= 0) continue;                                                \
                lane[l].point = j_;                                                            \
                lane[l].it = 0;                                                                \
                lane[l].h = 0.0;                                                               \
                for (int i_ = 0; i_ < CHAPLYGIN_N_PARAM; ++i_)                                 \
                    P[i_][l] = PP[j_ * CHAPLYGIN_N_PARAM + i_];                                \
                cvl_start(&lane[l], l, zl, k, PP + j_ * CHAPLYGIN_N_PARAM, TAU[j_], T0[j_],     \
                          rtol, atol, z, K[0], st_);                                           \
                break;                                                                         \
            }                                                                                  \
        } while (0)
    for (int l = 0; l < BM_W; ++l) {
        CVL_REFILL(l);
        if (lane[l].point >= 0) ++active;
    }
    if (active > 0) { /* idle lanes copy a working lane so that they compute finite numbers */
        int w = 0;
        while (lane[w].point < 0) ++w;
        for (int l = 0; l < BM_W; ++l) {
            if (lane[l].point >= 0) continue;
            for (int i = 0; i < mz; ++i) {
                z[i][l] = z[i][w];
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
            cvl_lane *L = &lane[l];
            tv[l] = L->t;
            last[l] = 0;
            if (L->point < 0) continue;
            const long j = L->point;
            int status = 0;
            if (++L->steps > max_steps) status = 1;
            else if (L->h < 10.0 * DBL_EPSILON * fmax(fabs(L->t), fabs(L->t1))) status = 2;
            if (status) {
                STATUS[j] = status; /* STATS[3]: the step size the interval started with */
                cvl_get(z, mz, l, Z + j * mz);
                CVL_REFILL(l);
                if (L->point < 0) { --active; continue; }
                --l; /* the new point starts in this lane: prepare its step */
                continue;
            }
            double h = L->h;
            if (h >= fabs(L->t1 - L->t)) {
                h = fabs(L->t1 - L->t);
                last[l] = 1;
            }
            hs[l] = h;
        }
        if (active == 0) break;
        /* the sums of variational.c, term by term in the same order over r; the loops over
         * the components innermost (independent: vectorised) */
        for (int s = 1; s < CV_STAGES; ++s) {
            for (int i = 0; i < mz; ++i) zs[i] = (bm_vec){0};
            for (int r = 0; r < s; ++r) {
                const double c = DOP_A[s * CV_STAGES + r];
                if (c == 0.0) continue;
                for (int i = 0; i < mz; ++i) zs[i] += c * K[r][i];
            }
            for (int i = 0; i < mz; ++i) zs[i] = z[i] + hs * zs[i];
            cvl_f(tv + DOP_C[s] * hs, zs, k, P, K[s]);
        }
        bm_vec tn = tv + hs;
        for (int i = 0; i < mz; ++i) zn[i] = (bm_vec){0};
        for (int r = 0; r < CV_STAGES; ++r) {
            if (DOP_B[r] == 0.0) continue;
            for (int i = 0; i < mz; ++i) zn[i] += DOP_B[r] * K[r][i];
        }
        for (int i = 0; i < mz; ++i) zn[i] = z[i] + hs * zn[i];
        for (int l = 0; l < BM_W; ++l)
            if (last[l]) tn[l] = lane[l].t1;
        cvl_f(tn, zn, k, P, K[CV_STAGES]);
        bm_vec a5[CV_ZMAX], a3[CV_ZMAX];
        for (int i = 0; i < m; ++i) a5[i] = a3[i] = (bm_vec){0};
        for (int r = 0; r <= CV_STAGES; ++r) {
            const double c5 = DOP_E5[r], c3 = DOP_E3[r];
            if (c5 != 0.0)
                for (int i = 0; i < m; ++i) a5[i] += c5 * K[r][i];
            if (c3 != 0.0)
                for (int i = 0; i < m; ++i) a3[i] += c3 * K[r][i];
        }
        bm_vec n5, n3;
        bm_error_sums_vec(a5, a3, z, zn, m, rtol, atol, &n5, &n3);
        for (int l = 0; l < BM_W; ++l) {
            cvl_lane *L = &lane[l];
            if (L->point < 0) continue;
            const long j = L->point;
            double *stats = STATS + 4 * j;
            stats[2] += CV_STAGES;
            double znl[CV_ZMAX];
            cvl_get(zn, mz, l, znl);
            const double h = hs[l];
            const double err = cvl_step_error(n5[l], n3[l], znl, m, mz, h);
            const double fac = bm_step_factor(err, L->rejected_last);
            if (err > 1.0) {
                L->h = h * fac;
                L->rejected_last = 1;
                stats[1] += 1;
                continue;
            }
            L->t = tn[l];
            for (int i = 0; i < mz; ++i) {
                z[i][l] = znl[i];
                K[0][i][l] = K[CV_STAGES][i][l];
            }
            stats[0] += 1;
            if (!last[l] || fac < 1.0) L->h = h * fac;
            L->rejected_last = 0;
            int status = cv_finite(znl, mz) ? 0 : 3;
            if (!status && !last[l]) continue;
            if (!status) { /* the end of an interval: renormalise outside the lanes */
                const double *p = PP + j * CHAPLYGIN_N_PARAM;
                stats[3] = L->h;
                status = cv_interval_end(L->t1, znl, k, p, project,
                                         LOGS + (j * n_intervals + L->it) * k,
                                         DIVS + j * n_intervals + L->it);
                L->it += 1;
                if (!status && L->it < n_intervals) {
                    cvl_start(L, l, znl, k, p, TAU[j], T0[j], rtol, atol, z, K[0], stats);
                    continue;
                }
            }
            STATUS[j] = status;
            for (int i = 0; i < mz; ++i) Z[j * mz + i] = znl[i];
            CVL_REFILL(l);
            if (L->point < 0) --active;
        }
    }
    #undef CVL_REFILL
}
#endif
