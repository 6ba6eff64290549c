/* taylorode: one-step Taylor schemes for stiff ODEs U' = f(t, U) + g(t, U), from C.
 *
 *   int status;
 *   taylorode_t *ode = taylorode_create("i-t-2", 2, &status);
 *   taylorode_set_functions(ode, f, g, jac_f, jac_g, &params);   (NULL Jacobians: differences)
 *   taylorode_set_tolerances(ode, 1e-6, 1e-6);
 *   status = taylorode_integrate(ode, 0.0, 1.0, u);               (or taylorode_init + taylorode_advance_to)
 *   if (status != TAYLORODE_OK) fprintf(stderr, "%s\n", taylorode_message(ode));
 *   taylorode_free(ode);
 *
 * Every function returns a status code and never stops or prints. A NULL handle, or
 * NULL for an array, a name or a result the function needs, is refused with
 * TAYLORODE_INVALID_ARGUMENT (and a message on the handle when there is one); nothing is
 * read or written through it. Names are exact C strings: "h0 " is no option, "i-t-2 "
 * no scheme. Every function that sets or integrates something leaves taylorode_message
 * "" when it succeeds and the reason when it fails. Memory the library cannot get is
 * TAYLORODE_OUT_OF_MEMORY, with a message naming the array and its bytes:
 * taylorode_create allocates nothing that grows with n (a huge n fails in taylorode_init
 * or taylorode_integrate, the state left as it was), taylorode_set_bandwidths and
 * taylorode_set_tolerance_vectors leave the settings as they were.
 *
 * Callbacks return
 * 0 on success, > 0 when they cannot evaluate at the point given (the step is
 * retried with a smaller step) and < 0 to stop the integration. Arrays are of length
 * n; dense Jacobians are column-major n x n (jac[i + n j] = d part_i / d u_j), band
 * Jacobians (after taylorode_set_bandwidths) use LAPACK's layout
 * jac[(upper + i - j) + (lower + upper + 1) j] for |i - j| within the band (0-based). */
#ifndef TAYLORODE_H
#define TAYLORODE_H

#ifdef __cplusplus
extern "C" {
#endif

/* Status codes (the library's status_* constants) */
enum {
  TAYLORODE_OK = 0,
  TAYLORODE_INVALID_ARGUMENT = 1,
  TAYLORODE_SIZE_MISMATCH = 2,
  TAYLORODE_NONFINITE = 3,
  TAYLORODE_SINGULAR_MATRIX = 4,
  TAYLORODE_NEWTON_DIVERGED = 5,
  TAYLORODE_NEWTON_NOT_CONVERGED = 6,
  TAYLORODE_STEP_UNDERFLOW = 7,
  TAYLORODE_MAX_STEPS = 8,
  TAYLORODE_UNKNOWN_SCHEME = 9,
  TAYLORODE_EVALUATION_FAILED = 10,
  TAYLORODE_OUTPUT_ERROR = 11,
  TAYLORODE_OUT_OF_MEMORY = 12 /* an array the integration needs could not be allocated (the message
                                  says which and how many bytes): the Newton matrices of a large n */
};

/* An integrator for one scheme and one problem size (opaque) */
typedef struct taylorode_s taylorode_t;

/* f or g: dudt = part(t, u) */
typedef int (*taylorode_rhs_fn)(double t, const double *u, double *dudt, void *user_data);
/* Jacobian of a part, dense or band storage */
typedef int (*taylorode_jac_fn)(double t, const double *u, double *jac, void *user_data);

/* What an integration did (since taylorode_init) */
typedef struct {
  long accepted_steps, rejected_steps, f_evaluations, g_evaluations, jacobian_evaluations, lu_factorizations,
      linear_solves, newton_iterations;
  double t_reached, h_next, cpu_seconds;
} taylorode_stats_t;

/* A handle for a scheme ("ex-t-1", "ex-t-2", "si-t-1", "si-t-2", "si-t-2-paper", "i-t-1", "i-t-2",
   "imex-rk21", "radau5") and n unknowns; NULL with *status set on failure (TAYLORODE_INVALID_ARGUMENT
   for a NULL scheme, TAYLORODE_UNKNOWN_SCHEME, TAYLORODE_SIZE_MISMATCH for n < 1). status may be NULL:
   the handle is created all the same, and a failure shows only as the NULL returned. */
taylorode_t *taylorode_create(const char *scheme, int n, int *status);
void taylorode_free(taylorode_t *ode);

/* f (non-stiff) and g (stiff); NULL f or g is zero, NULL Jacobians come from differences */
int taylorode_set_functions(taylorode_t *ode, taylorode_rhs_fn f, taylorode_rhs_fn g, taylorode_jac_fn jac_f,
                            taylorode_jac_fn jac_g, void *user_data);
/* Banded Jacobians: J(i, j) = 0 for i - j > lower or j - i > upper */
int taylorode_set_bandwidths(taylorode_t *ode, int lower, int upper);
int taylorode_set_tolerances(taylorode_t *ode, double rtol, double atol);
int taylorode_set_tolerance_vectors(taylorode_t *ode, const double *rtol, const double *atol);
/* Options by name: "h0", "h_min", "h_min_relative", "h_max", "kappa", "q", "max_growth", "min_shrink", "newton_fraction",
   "max_steps", "max_newton_iterations", "max_failures", "reuse_newton_matrix" (0/1), "measure_time" (0/1:
   1, the default, measures each call's CPU time, which costs two system calls per call),
   "controller" (0: I, 1: PI, 2: PID), "norm" (0: max, 1: rms); and the problem's "autonomous" (1: f and g
   do not depend on t, which saves the second-order Taylor schemes their differences in t; 0, the
   default: they may) */
int taylorode_set_option(taylorode_t *ode, const char *name, double value);

/* Start at (t0, u0); then continue call after call (u may be changed between calls) to any t not
   before the current time (t equal to it returns at once). Settings (bandwidths, tolerances,
   options) apply from taylorode_init on: one changed after it ends the integration under way, and
   taylorode_advance_to asks for taylorode_init again */
int taylorode_init(taylorode_t *ode, double t0, const double *u0);
int taylorode_advance_to(taylorode_t *ode, double t, double *u);
/* From t0 to t_end > t0 in one call (t_end <= t0 is refused, u untouched): u holds u(t0) on entry,
   u(t_end) (or the last good state) on exit */
int taylorode_integrate(taylorode_t *ode, double t0, double t_end, double *u);

/* Statistics since taylorode_init; it only reads, and leaves the message as it was unless it fails */
int taylorode_get_stats(const taylorode_t *ode, taylorode_stats_t *stats);
/* The message of the last call on ode ("" when it succeeded), valid until the next call on ode;
   never NULL (for a NULL ode, a text that says so) */
const char *taylorode_message(const taylorode_t *ode);

#ifdef __cplusplus
}
#endif

#endif /* TAYLORODE_H */
