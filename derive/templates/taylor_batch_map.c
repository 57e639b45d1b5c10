/* chaplygin.numerics.dynamics.batch_map: the stroboscopic map of many points in one call, by the
 * model's generated Taylor integrator.
 *
 * Appended to a model's emitted Taylor C source (generated/<model>_taylor.c, the double build:
 * chaplygin_taylor_run and the order/step-size/recurrence functions it calls), preceded by
 * bm_time (templates/batch_time.c, also in batch_map.c) and the lanes driver
 * (templates/taylor_lanes.c; c_sources.taylor_batch_source). Each
 * of N points has its own state, parameter vector and sampling times
 *     t_k = t0 + k tau,  tau = tau_hi + tau_lo (a double-double), k = transient ..
 *     transient + n_record - 1,
 * each t_k rounded once (bm_time). Every point is integrated from t0 to its last sampling
 * time by chaplygin_taylor_run_lanes, TL_W points at a time in vector lanes, each point's
 * numbers bit-identical to a chaplygin_taylor_run call on it: the steps of the single-point
 * integrator (Jorba & Zou's order
 * and step size; the last step shortened to land exactly on the final time), and the map
 * points are the step polynomials evaluated at the t_k inside their steps (dense output: the
 * sampling times do not change the steps). No Python runs per step or per period. Points are
 * independent: one that fails (non-finite value, step limit, step-size underflow) gets its
 * own status and NaN points, and the others are unaffected. Double precision only.
 *
 * chaplygin_taylor_batch_map(N, Y0, P, T0, TAU_HI, TAU_LO, transient, n_record, rtol, atol,
 *                            max_steps, OUT, STATS, STATUS)
 *   Y0   N x n_state       initial states (row per point)
 *   P    N x n_param       parameters (row per point)
 *   OUT  N x n_record x n_state: y(t_k) (all NaN for a point that failed)
 *   STATS N x 3: Taylor steps, lowest order, highest order
 *   STATUS N: 0 done, 1 step limit (max_steps per period on average), 2 step-size underflow,
 *             3 non-finite, 4 out of memory
 *   max_steps: steps allowed per forcing period (the point's budget is max_steps times
 *              its periods, at least max_steps)
 */
#include <limits.h>
#include <math.h>
#include <stdlib.h>

void chaplygin_taylor_batch_map(long N, const double *Y0, const double *P, const double *T0,
                                const double *TAU_HI, const double *TAU_LO, long transient,
                                long n_record, double rtol, double atol, long max_steps,
                                double *OUT, double *STATS, int *STATUS)
{
    const int n = CHAPLYGIN_TAYLOR_N_STATE;
    const double ctrl[3] = {rtol, atol, 0.0};
    const long periods = transient + n_record - 1;
    const long budget = periods > 1 ? (max_steps > LONG_MAX / periods ? LONG_MAX
                                                                       : max_steps * periods)
                                     : max_steps;
    double *times = malloc(sizeof(double) * (size_t)(N * n_record + 1));
    double *t01 = malloc(sizeof(double) * (size_t)(2 * N + 1));
    double *y_end = malloc(sizeof(double) * (size_t)(N * n + 1));
    double *t_reached = malloc(sizeof(double) * (size_t)(N + 1));
    long *run_stats = malloc(sizeof(long) * (size_t)(4 * N + 4));
    int *run = malloc(sizeof(int) * (size_t)(N + 1));
    const int memory = times && t01 && y_end && t_reached && run_stats && run;
    for (long j = 0; j < N; ++j) { /* the points that run, their sampling times */
        int status = memory ? 0 : 4;
        for (int i = 0; i < n && !status; ++i)
            if (!isfinite(Y0[j * n + i])) status = 3;
        for (int i = 0; i < CHAPLYGIN_TAYLOR_N_PARAM && !status; ++i)
            if (!isfinite(P[j * CHAPLYGIN_TAYLOR_N_PARAM + i])) status = 3;
        STATUS[j] = status;
        STATS[3 * j] = STATS[3 * j + 1] = STATS[3 * j + 2] = 0.0;
        if (!memory) continue;
        run[j] = status;
        for (long k = 0; k < n_record; ++k)
            times[j * n_record + k] = bm_time(T0[j], transient + k, TAU_HI[j], TAU_LO[j]);
        t01[2 * j] = T0[j];
        t01[2 * j + 1] = times[j * n_record + n_record - 1];
    }
    if (memory && chaplygin_taylor_run_lanes(N, t01, Y0, P, ctrl, 0, n_record, times, n_record,
                                             OUT, y_end, t_reached, budget, run_stats, run))
        for (long j = 0; j < N; ++j) STATUS[j] = 4;
    for (long j = 0; j < N; ++j) {
        double *out = OUT + j * n_record * n, *stats = STATS + 3 * j;
        int status = STATUS[j];
        if (!status) {
            stats[0] = (double)run_stats[4 * j];
            stats[1] = (double)run_stats[4 * j + 2];
            stats[2] = (double)run_stats[4 * j + 1];
            if (run[j] == -2) status = 1;
            else if (run[j] == -3) status = 2;
            else if (run[j] == -1) status = 3;
            else if (run[j] != 0) status = 4;
            else if (run_stats[4 * j + 3] != n_record) status = 3; /* not every time reached */
            for (long i = 0; i < n_record * n && !status; ++i)
                if (!isfinite(out[i])) status = 3;
        }
        if (status)
            for (long i = 0; i < n_record * n; ++i) out[i] = NAN;
        STATUS[j] = status;
    }
    free(times);
    free(t01);
    free(y_end);
    free(t_reached);
    free(run_stats);
    free(run);
}
