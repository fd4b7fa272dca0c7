/* SUNDIALS CVODE (Debian's libsundials, 6.4) on the peer problems: a compiled peer with
 * event location, written as a researcher would write it, mirroring scipy_peers.py.
 *
 *   cc -O2 -o cvode_peer cvode_peer.c -lsundials_cvode -lsundials_nvecserial -lm
 *   cvode_peer PROBLEM.txt METHOD RTOL REPEATS
 *
 * PROBLEM.txt (written by run.py from the library's matrices, examples/peer_problem.rs):
 * whitespace-separated numbers in this order:
 *   model (0 compliant, 1 rigid)  N  periods  period  omega  gap
 *   K- (N×N, row-major)  K+ (N×N)  damping (N)  forcing (N)  tip (N)  contact preload (N)
 *   law (N×N, the rigid model's η̇⁺ = −law η̇⁻)  x0 (2N)
 * METHOD: bdf (BDF with Newton and a dense linear solver given the exact Jacobian, which
 * is constant between events: the system is linear in each region) or adams (Adams with
 * fixed-point iteration, CVODE's non-stiff setting). Absolute tolerance 1e-3 RTOL.
 *
 * The model, in first-order form x = [η; η̇]:
 *   ẋ = [η̇; −K^± η − C η̇ + f cos ωt + F^±],  F⁻ = 0, F⁺ = the contact preload.
 * Compliant: free flight while tipᵀη < d₀ (K⁻), contact while tipᵀη ≥ d₀ (K⁺); CVODE's root
 * finding on g = tipᵀη − d₀ in the direction that leaves the current region; at each root
 * the region switches and CVODE is restarted there (CVodeReInit).
 * Rigid: the free flow; a root of g approached from below is an impact: if the tip's
 * velocity is positive the law η̇⁺ = −law η̇⁻ is applied and CVODE is restarted. No chatter
 * policy: as scipy_peers.rigid, a run whose impacts pile up (more than 1000 per period, or
 * 50 in a row without time advancing by 1e-12 T) stops and says so.
 *
 * Timing: the solve alone — from the first CVodeReInit at t = 0 to the end, every restart,
 * root and reset included — by clock_gettime(CLOCK_PROCESS_CPUTIME_ID), repeated REPEATS
 * times in this process (stopping early once the repeats used 1 s of CPU); reading the
 * input, creating CVODE's memory, vectors, matrix and solvers (once), and the output are
 * not timed. One thread.
 *
 * Prints one JSON object: cpu_seconds (each repeat), setup_cpu_seconds, strobe (the state
 * at every period end reached), state (the final state), events ([t, entering] each),
 * rhs_evaluations, outcome.
 */

#include <cvode/cvode.h>
#include <math.h>
#include <nvector/nvector_serial.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sundials/sundials_context.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>
#include <sunnonlinsol/sunnonlinsol_fixedpoint.h>
#include <time.h>

#define MAX_EVENTS_PER_PERIOD 1000

typedef struct {
    int rigid, n, periods;
    double period, omega, gap;
    double *kminus, *kplus, *c, *f, *tip, *preload, *law, *x0;
    int contact; /* the current region (compliant model) */
} Problem;

static double *read_numbers(FILE *in, int count) {
    double *v = malloc(sizeof(double) * (count > 0 ? count : 1));
    for (int i = 0; i < count; i++) {
        if (fscanf(in, "%lf", &v[i]) != 1) {
            fprintf(stderr, "cvode_peer: the problem file ends early\n");
            exit(2);
        }
    }
    return v;
}

static double cpu_now(void) {
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

static int rhs(realtype t, N_Vector xv, N_Vector dxv, void *data) {
    const Problem *p = data;
    const int n = p->n;
    const double *x = N_VGetArrayPointer(xv);
    double *dx = N_VGetArrayPointer(dxv);
    const double *k = p->contact ? p->kplus : p->kminus;
    const double forcing = cos(p->omega * t);
    for (int i = 0; i < n; i++) {
        double a = p->f[i] * forcing - p->c[i] * x[n + i];
        if (p->contact) a += p->preload[i];
        const double *row = k + (size_t)i * n;
        for (int j = 0; j < n; j++) a -= row[j] * x[j];
        dx[i] = x[n + i];
        dx[n + i] = a;
    }
    return 0;
}

static int jac(realtype t, N_Vector x, N_Vector fx, SUNMatrix J, void *data, N_Vector t1,
               N_Vector t2, N_Vector t3) {
    (void)t, (void)x, (void)fx, (void)t1, (void)t2, (void)t3;
    const Problem *p = data;
    const int n = p->n;
    const double *k = p->contact ? p->kplus : p->kminus;
    SUNMatZero(J);
    for (int i = 0; i < n; i++) {
        SM_ELEMENT_D(J, i, n + i) = 1.0;
        SM_ELEMENT_D(J, n + i, n + i) = -p->c[i];
        for (int j = 0; j < n; j++) SM_ELEMENT_D(J, n + i, j) = -k[(size_t)i * n + j];
    }
    return 0;
}

static double tip_gap(const Problem *p, const double *x) {
    double g = -p->gap;
    for (int i = 0; i < p->n; i++) g += p->tip[i] * x[i];
    return g;
}

static double tip_velocity(const Problem *p, const double *x) {
    double v = 0.0;
    for (int i = 0; i < p->n; i++) v += p->tip[i] * x[p->n + i];
    return v;
}

static int root(realtype t, N_Vector x, realtype *g, void *data) {
    (void)t;
    *g = tip_gap(data, N_VGetArrayPointer(x));
    return 0;
}

/* The library's rule (model.py's starting_region): contact if d > d₀; on the surface, if
 * the tip moves into the stop or, at rest, if its free acceleration does. */
static int starting_contact(const Problem *p, const double *x) {
    const int n = p->n;
    double d = tip_gap(p, x), v = tip_velocity(p, x), acc = 0.0;
    for (int i = 0; i < n; i++) {
        double a = p->f[i] - p->c[i] * x[n + i];
        for (int j = 0; j < n; j++) a -= p->kminus[(size_t)i * n + j] * x[j];
        acc += p->tip[i] * a;
    }
    return d > 0 || (d == 0 && (v > 0 || (v == 0 && acc > 0)));
}

typedef struct {
    double *strobe; /* periods × 2N */
    int strobes;
    double *event_t;
    int *event_kind;
    int events, cap;
    long nfev;
    double t;
    char outcome[256];
} Run;

/* One run from x0 at t = 0 over the problem's periods (the timed part). */
static void solve(Problem *p, void *mem, N_Vector y, Run *r) {
    const int n2 = 2 * p->n;
    const double t_end = p->periods * p->period;
    double *x = N_VGetArrayPointer(y);
    memcpy(x, p->x0, sizeof(double) * n2);
    double t = 0.0, last = 0.0;
    int stalled = 0, k = 1;
    long nf;
    r->strobes = 0;
    r->events = 0;
    r->nfev = 0;
    strcpy(r->outcome, "completed");
    p->contact = p->rigid ? 0 : starting_contact(p, x);
    int dir;
    while (t < t_end) {
        CVodeReInit(mem, t, y);
        CVodeSetStopTime(mem, t_end);
        dir = p->rigid ? 1 : (p->contact ? -1 : 1);
        CVodeSetRootDirection(mem, &dir);
        int flag = CV_SUCCESS;
        while (k <= p->periods) {
            double tout = k * p->period;
            if (tout <= t) { /* a period end at the restart itself is not revisited */
                k++;
                continue;
            }
            realtype tret;
            flag = CVode(mem, tout, y, &tret, CV_NORMAL);
            if (flag < 0) {
                CVodeGetNumRhsEvals(mem, &nf);
                r->nfev += nf;
                snprintf(r->outcome, sizeof r->outcome, "failed at t = %.6g: %s", t,
                         CVodeGetReturnFlagName(flag));
                r->t = t;
                return;
            }
            t = tret;
            if (flag == CV_ROOT_RETURN) break;
            memcpy(r->strobe + (size_t)r->strobes * n2, x, sizeof(double) * n2);
            r->strobes++;
            k++;
        }
        CVodeGetNumRhsEvals(mem, &nf);
        r->nfev += nf;
        if (flag != CV_ROOT_RETURN) {
            t = t_end;
            break;
        }
        if (p->rigid) {
            double v_in = tip_velocity(p, x);
            if (v_in > 0) {
                const int n = p->n;
                double v[n];
                for (int i = 0; i < n; i++) {
                    v[i] = 0.0;
                    for (int j = 0; j < n; j++) v[i] -= p->law[(size_t)i * n + j] * x[n + j];
                }
                memcpy(x + n, v, sizeof(double) * n);
                r->event_t[r->events] = t;
                r->event_kind[r->events] = 1;
                r->events++;
            }
            stalled = (t - last < 1e-12 * p->period) ? stalled + 1 : 0;
            last = t;
            if (stalled >= 50) {
                snprintf(r->outcome, sizeof r->outcome,
                         "stalled at t = %.6g: 50 impacts without time advancing by 1e-12 T "
                         "(impacts accumulate: chatter)", t);
                break;
            }
            if (r->events > r->cap) {
                snprintf(r->outcome, sizeof r->outcome,
                         "stopped at t = %.6g: more than %d impacts (impacts accumulate: chatter)",
                         t, r->cap);
                break;
            }
        } else {
            r->event_t[r->events] = t;
            r->event_kind[r->events] = !p->contact;
            r->events++;
            p->contact = !p->contact;
            if (r->events > r->cap) {
                snprintf(r->outcome, sizeof r->outcome,
                         "stopped at t = %.6g: more than %d switches", t, r->cap);
                break;
            }
        }
    }
    r->t = t;
}

static void print_vector(const double *x, int n) {
    printf("[");
    for (int i = 0; i < n; i++) printf(i ? ", %.17g" : "%.17g", x[i]);
    printf("]");
}

int main(int argc, char **argv) {
    if (argc != 5) {
        fprintf(stderr, "usage: cvode_peer PROBLEM.txt bdf|adams RTOL REPEATS\n");
        return 2;
    }
    const int bdf = strcmp(argv[2], "bdf") == 0;
    if (!bdf && strcmp(argv[2], "adams") != 0) {
        fprintf(stderr, "cvode_peer: method %s: bdf or adams\n", argv[2]);
        return 2;
    }
    const double rtol = atof(argv[3]), atol = 1e-3 * rtol;
    const int repeats = atoi(argv[4]) > 0 ? atoi(argv[4]) : 1;
    FILE *in = fopen(argv[1], "r");
    if (!in) {
        perror(argv[1]);
        return 2;
    }
    double *head = read_numbers(in, 6);
    Problem p = {.rigid = (int)head[0], .n = (int)head[1], .periods = (int)head[2],
                 .period = head[3], .omega = head[4], .gap = head[5]};
    const int n = p.n, n2 = 2 * n;
    p.kminus = read_numbers(in, n * n);
    p.kplus = read_numbers(in, n * n);
    p.c = read_numbers(in, n);
    p.f = read_numbers(in, n);
    p.tip = read_numbers(in, n);
    p.preload = read_numbers(in, n);
    p.law = read_numbers(in, n * n);
    p.x0 = read_numbers(in, n2);
    fclose(in);

    /* set-up (not timed in the solve's time; its own CPU time is reported) */
    double setup_start = cpu_now();
    SUNContext ctx;
    SUNContext_Create(NULL, &ctx);
    N_Vector y = N_VNew_Serial(n2, ctx);
    memcpy(N_VGetArrayPointer(y), p.x0, sizeof(double) * n2);
    void *mem = CVodeCreate(bdf ? CV_BDF : CV_ADAMS, ctx);
    CVodeInit(mem, rhs, 0.0, y);
    CVodeSStolerances(mem, rtol, atol);
    CVodeSetUserData(mem, &p);
    CVodeSetMaxNumSteps(mem, 100000000L);
    CVodeSetMaxHnilWarns(mem, -1);
    CVodeRootInit(mem, 1, root);
    CVodeSetNoInactiveRootWarn(mem);
    SUNMatrix a = NULL;
    SUNLinearSolver ls = NULL;
    SUNNonlinearSolver nls = NULL;
    if (bdf) {
        a = SUNDenseMatrix(n2, n2, ctx);
        ls = SUNLinSol_Dense(y, a, ctx);
        CVodeSetLinearSolver(mem, ls, a);
        CVodeSetJacFn(mem, jac);
    } else {
        nls = SUNNonlinSol_FixedPoint(y, 0, ctx);
        CVodeSetNonlinearSolver(mem, nls);
    }
    Run r = {.cap = MAX_EVENTS_PER_PERIOD * (p.periods > 1 ? p.periods : 1)};
    r.strobe = malloc(sizeof(double) * (size_t)(p.periods + 1) * n2);
    r.event_t = malloc(sizeof(double) * (size_t)(r.cap + 2));
    r.event_kind = malloc(sizeof(int) * (size_t)(r.cap + 2));
    double setup = cpu_now() - setup_start;

    double *seconds = malloc(sizeof(double) * repeats);
    int done = 0;
    double spent = 0.0;
    for (int i = 0; i < repeats; i++) {
        double t0 = cpu_now();
        solve(&p, mem, y, &r);
        seconds[i] = cpu_now() - t0;
        spent += seconds[i];
        done++;
        if (spent > 1.0) break;
    }

    printf("{\"cpu_seconds\": ");
    print_vector(seconds, done);
    printf(", \"setup_cpu_seconds\": %.17g, \"strobe\": [", setup);
    for (int i = 0; i < r.strobes; i++) {
        if (i) printf(", ");
        print_vector(r.strobe + (size_t)i * n2, n2);
    }
    printf("], \"state\": ");
    print_vector(N_VGetArrayPointer(y), n2);
    printf(", \"time\": %.17g, \"events\": [", r.t);
    for (int i = 0; i < r.events; i++)
        printf(i ? ", [%.17g, %s]" : "[%.17g, %s]", r.event_t[i], r.event_kind[i] ? "true" : "false");
    printf("], \"rhs_evaluations\": %ld, \"outcome\": \"%s\"}\n", r.nfev, r.outcome);

    CVodeFree(&mem);
    if (ls) SUNLinSolFree(ls);
    if (a) SUNMatDestroy(a);
    if (nls) SUNNonlinSolFree(nls);
    N_VDestroy(y);
    SUNContext_Free(&ctx);
    return 0;
}
