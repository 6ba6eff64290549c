/* The C interface's promises on bad input, checked by a C program as a C caller would
 * call the library: NULL for every pointer argument, names with blanks, t_end = t0,
 * and the message after a failed call followed by a good one (include/taylorode.h).
 * It prints one line per check ("ok ..." or "FAIL ...") and exits with the number of
 * failures. test_interfaces builds it against the installed library with
 * -DTAYLORODE_CONTRACT_PROGRAM and runs it in a process of its own, so that a crash
 * fails that one test. fpm, which compiles every C file under test/ into the test
 * program, compiles it without that definition: to nothing. */
#ifdef TAYLORODE_CONTRACT_PROGRAM

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "taylorode.h"

static int failures = 0;

static void expect(int condition, const char *what, const char *detail) {
  if (condition) {
    printf("ok %s\n", what);
  } else {
    printf("FAIL %s: %s\n", what, detail ? detail : "");
    failures++;
  }
  fflush(stdout);
}

/* A status is the one expected and the handle says why in words (never empty) */
static void expect_refused(int status, int expected, taylorode_t *ode, const char *what) {
  const char *message = taylorode_message(ode);
  expect(status == expected && message != NULL && message[0] != '\0', what, message);
}

static int decay(double t, const double *u, double *dudt, void *data) {
  (void)t;
  (void)data;
  dudt[0] = -u[0];
  return 0;
}

int main(void) {
  int status = -1, code;
  taylorode_t *ode, *other;
  taylorode_stats_t stats;
  double u[1] = {1.0}, tolerances[1] = {1e-6};
  const char *message;

  /* taylorode_create: a NULL name, a NULL status, names with blanks */
  ode = taylorode_create(NULL, 1, &status);
  expect(ode == NULL && status == TAYLORODE_INVALID_ARGUMENT, "create with a NULL scheme name", NULL);
  other = taylorode_create("i-t-2", 1, NULL);
  expect(other != NULL, "create with a NULL status pointer still creates the handle", NULL);
  taylorode_free(other);
  other = taylorode_create("no-such-scheme", 1, NULL);
  expect(other == NULL, "create failing with a NULL status pointer returns NULL", NULL);
  other = taylorode_create("i-t-2 ", 1, &status);
  expect(other == NULL && status == TAYLORODE_UNKNOWN_SCHEME, "create with a trailing blank in the name", NULL);
  other = taylorode_create(" i-t-2", 1, &status);
  expect(other == NULL && status == TAYLORODE_UNKNOWN_SCHEME, "create with a leading blank in the name", NULL);

  /* every function with a NULL handle: an error, and a message that says so */
  message = taylorode_message(NULL);
  expect(message != NULL && message[0] != '\0', "message of a NULL handle is a text", NULL);
  expect(taylorode_set_functions(NULL, decay, NULL, NULL, NULL, NULL) == TAYLORODE_INVALID_ARGUMENT,
         "set_functions(NULL, ...)", NULL);
  expect(taylorode_set_bandwidths(NULL, 0, 0) == TAYLORODE_INVALID_ARGUMENT, "set_bandwidths(NULL, ...)", NULL);
  expect(taylorode_set_tolerances(NULL, 1e-6, 1e-6) == TAYLORODE_INVALID_ARGUMENT, "set_tolerances(NULL, ...)",
         NULL);
  expect(taylorode_set_tolerance_vectors(NULL, tolerances, tolerances) == TAYLORODE_INVALID_ARGUMENT,
         "set_tolerance_vectors(NULL, ...)", NULL);
  expect(taylorode_set_option(NULL, "h0", 1e-3) == TAYLORODE_INVALID_ARGUMENT, "set_option(NULL, ...)", NULL);
  expect(taylorode_init(NULL, 0.0, u) == TAYLORODE_INVALID_ARGUMENT, "init(NULL, ...)", NULL);
  expect(taylorode_advance_to(NULL, 1.0, u) == TAYLORODE_INVALID_ARGUMENT, "advance_to(NULL, ...)", NULL);
  expect(taylorode_integrate(NULL, 0.0, 1.0, u) == TAYLORODE_INVALID_ARGUMENT, "integrate(NULL, ...)", NULL);
  expect(taylorode_get_stats(NULL, &stats) == TAYLORODE_INVALID_ARGUMENT, "get_stats(NULL, ...)", NULL);
  taylorode_free(NULL);

  ode = taylorode_create("i-t-2", 1, &status);
  expect(ode != NULL && status == TAYLORODE_OK, "create i-t-2", NULL);
  if (ode == NULL) return failures;
  expect(taylorode_set_functions(ode, NULL, decay, NULL, NULL, NULL) == TAYLORODE_OK, "set_functions", NULL);

  /* NULL arrays, names and results with a handle */
  expect_refused(taylorode_set_tolerance_vectors(ode, NULL, NULL), TAYLORODE_INVALID_ARGUMENT, ode,
                 "set_tolerance_vectors(ode, NULL, NULL)");
  expect_refused(taylorode_set_tolerance_vectors(ode, tolerances, NULL), TAYLORODE_INVALID_ARGUMENT, ode,
                 "set_tolerance_vectors(ode, rtol, NULL)");
  expect_refused(taylorode_set_tolerance_vectors(ode, NULL, tolerances), TAYLORODE_INVALID_ARGUMENT, ode,
                 "set_tolerance_vectors(ode, NULL, atol)");
  expect_refused(taylorode_set_option(ode, NULL, 1.0), TAYLORODE_INVALID_ARGUMENT, ode, "set_option(ode, NULL, 1)");
  expect_refused(taylorode_init(ode, 0.0, NULL), TAYLORODE_INVALID_ARGUMENT, ode, "init(ode, 0, NULL)");
  expect_refused(taylorode_integrate(ode, 0.0, 1.0, NULL), TAYLORODE_INVALID_ARGUMENT, ode,
                 "integrate(ode, 0, 1, NULL)");
  expect(taylorode_init(ode, 0.0, u) == TAYLORODE_OK, "init", taylorode_message(ode));
  expect_refused(taylorode_advance_to(ode, 1.0, NULL), TAYLORODE_INVALID_ARGUMENT, ode, "advance_to(ode, 1, NULL)");
  expect_refused(taylorode_get_stats(ode, NULL), TAYLORODE_INVALID_ARGUMENT, ode, "get_stats(ode, NULL)");

  /* option names are exact: no blank before or after */
  expect_refused(taylorode_set_option(ode, "h0 ", 1e-3), TAYLORODE_INVALID_ARGUMENT, ode, "option \"h0 \"");
  expect_refused(taylorode_set_option(ode, " h0", 1e-3), TAYLORODE_INVALID_ARGUMENT, ode, "option \" h0\"");
  expect_refused(taylorode_set_option(ode, "", 1e-3), TAYLORODE_INVALID_ARGUMENT, ode, "option \"\"");
  expect(taylorode_set_option(ode, "h0", 1e-3) == TAYLORODE_OK, "option \"h0\"", taylorode_message(ode));
  /* the problem's autonomy: 0 or 1 */
  expect_refused(taylorode_set_option(ode, "autonomous", 2.0), TAYLORODE_INVALID_ARGUMENT, ode, "autonomous = 2");
  expect(taylorode_set_option(ode, "autonomous", 1.0) == TAYLORODE_OK, "autonomous = 1", taylorode_message(ode));

  /* t_end must lie after t0, as in the Fortran integrate; advance_to may stay put */
  u[0] = 1.0;
  expect_refused(taylorode_integrate(ode, 1.0, 1.0, u), TAYLORODE_INVALID_ARGUMENT, ode, "integrate with t_end = t0");
  expect_refused(taylorode_integrate(ode, 1.0, 0.5, u), TAYLORODE_INVALID_ARGUMENT, ode, "integrate with t_end < t0");
  expect_refused(taylorode_integrate(ode, 0.0, NAN, u), TAYLORODE_INVALID_ARGUMENT, ode, "integrate to NaN");
  expect(u[0] == 1.0, "a refused integrate leaves u alone", NULL);
  /* measure_time: 0 or 1; with 0 the statistics hold no CPU time */
  expect_refused(taylorode_set_option(ode, "measure_time", 2.0), TAYLORODE_INVALID_ARGUMENT, ode, "measure_time = 2");
  expect(taylorode_set_option(ode, "measure_time", 0.0) == TAYLORODE_OK, "measure_time = 0", taylorode_message(ode));
  expect(taylorode_integrate(ode, 0.0, 1.0, u) == TAYLORODE_OK && fabs(u[0] - exp(-1.0)) < 1e-4,
         "integrate from 0 to 1", taylorode_message(ode));
  expect(taylorode_get_stats(ode, &stats) == TAYLORODE_OK && stats.cpu_seconds == 0.0 && stats.accepted_steps > 0,
         "no CPU time measured with measure_time = 0", taylorode_message(ode));
  expect(taylorode_advance_to(ode, 1.0, u) == TAYLORODE_OK, "advance_to the current time returns at once",
         taylorode_message(ode));
  expect_refused(taylorode_advance_to(ode, 0.5, u), TAYLORODE_INVALID_ARGUMENT, ode, "advance_to before the current time");

  /* a failed call, then a good one: the message is empty again, for every function
     that sets something; get_stats only reads, and leaves a failure's message */
#define FAIL_THEN(call, what)                                                                              \
  taylorode_set_option(ode, "no_such_option", 1.0);                                                        \
  code = (call);                                                                                           \
  expect(code == TAYLORODE_OK && taylorode_message(ode)[0] == '\0', "message cleared by a good " what,     \
         taylorode_message(ode));
  FAIL_THEN(taylorode_set_functions(ode, NULL, decay, NULL, NULL, NULL), "set_functions")
  FAIL_THEN(taylorode_set_tolerances(ode, 1e-6, 1e-6), "set_tolerances")
  FAIL_THEN(taylorode_set_tolerance_vectors(ode, tolerances, tolerances), "set_tolerance_vectors")
  FAIL_THEN(taylorode_set_option(ode, "h0", 1e-3), "set_option")
  FAIL_THEN(taylorode_set_bandwidths(ode, 0, 0), "set_bandwidths")
  u[0] = 1.0;
  FAIL_THEN(taylorode_init(ode, 0.0, u), "init")
  FAIL_THEN(taylorode_advance_to(ode, 1.0, u), "advance_to")
  u[0] = 1.0;
  FAIL_THEN(taylorode_integrate(ode, 0.0, 1.0, u), "integrate")
  taylorode_set_option(ode, "no_such_option", 1.0);
  expect(taylorode_get_stats(ode, &stats) == TAYLORODE_OK && strstr(taylorode_message(ode), "no_such_option"),
         "get_stats leaves the message of the failure before it", taylorode_message(ode));

  /* bandwidths changed after init: the scheme's matrices were made for the old ones, so
     advance_to is refused until init again (it read the new work array with the old bands:
     an invalid read, a double free before) */
  u[0] = 1.0;
  expect(taylorode_set_bandwidths(ode, 0, 0) == TAYLORODE_OK && taylorode_init(ode, 0.0, u) == TAYLORODE_OK,
         "init with bands 0, 0", taylorode_message(ode));
  expect(taylorode_set_bandwidths(ode, 0, 0) == TAYLORODE_OK, "set_bandwidths after init", taylorode_message(ode));
  expect_refused(taylorode_advance_to(ode, 1.0, u), TAYLORODE_INVALID_ARGUMENT, ode, "advance_to after set_bandwidths");
  expect(taylorode_init(ode, 0.0, u) == TAYLORODE_OK && taylorode_advance_to(ode, 1.0, u) == TAYLORODE_OK,
         "init again, then advance_to", taylorode_message(ode));

  /* any setting changed after init likewise ends the integration under way (it went on
     with the settings of init, and returned TAYLORODE_OK for the new ones, ignored) */
  expect(taylorode_set_tolerances(ode, 1e-9, 1e-9) == TAYLORODE_OK, "set_tolerances after init", taylorode_message(ode));
  expect_refused(taylorode_advance_to(ode, 2.0, u), TAYLORODE_INVALID_ARGUMENT, ode, "advance_to after set_tolerances");
  expect(taylorode_init(ode, 1.0, u) == TAYLORODE_OK, "init again", taylorode_message(ode));
  expect(taylorode_set_tolerance_vectors(ode, tolerances, tolerances) == TAYLORODE_OK,
         "set_tolerance_vectors after init", taylorode_message(ode));
  expect_refused(taylorode_advance_to(ode, 2.0, u), TAYLORODE_INVALID_ARGUMENT, ode,
                 "advance_to after set_tolerance_vectors");
  expect(taylorode_init(ode, 1.0, u) == TAYLORODE_OK, "init again", taylorode_message(ode));
  expect(taylorode_set_option(ode, "max_steps", 1.0) == TAYLORODE_OK, "set_option after init", taylorode_message(ode));
  expect_refused(taylorode_advance_to(ode, 2.0, u), TAYLORODE_INVALID_ARGUMENT, ode, "advance_to after set_option");
  expect(taylorode_init(ode, 1.0, u) == TAYLORODE_OK && taylorode_advance_to(ode, 2.0, u) == TAYLORODE_MAX_STEPS,
         "init again: the step budget of 1 applies", taylorode_message(ode));

  taylorode_free(ode);
  printf("%d failed\n", failures);
  return failures;
}

#else
/* compiled into the test program by fpm: nothing */
typedef int taylorode_contract_program_not_built_here;
#endif
