/* Integrations through the C interface that cannot get their memory end with
 * TAYLORODE_OUT_OF_MEMORY and a message, never a crash: test_memory builds this program
 * against the installed library with -DTAYLORODE_MEMORY_PROGRAM and runs it under a
 * reduced address-space limit (ulimit -v). "measure" runs the small problem only and
 * prints the program's peak address space in kB, from which the test sets the limit:
 * that peak plus 300 MB. Without an argument the small problem must still succeed under
 * it; each band problem (n = 50000, bandwidths 200: 160 MB for the band Jacobians' work
 * array alone) then asks for more than the limit leaves, and one dense problem of
 * n = 5000000 for more than any address space holds. One line per integration:
 * "<scheme> n <n> band <b>: status <code>: <message>". fpm, which compiles every C file
 * under test/ into the test program, compiles it without that definition: to nothing. */
#ifdef TAYLORODE_MEMORY_PROGRAM

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "taylorode.h"

/* u_i' = -u_i + 0.1 (u_(i-1) + u_(i+1)) */
static int chain(double t, const double *u, double *dudt, void *data) {
  int n = *(const int *)data, i;
  (void)t;
  for (i = 0; i < n; i++) {
    dudt[i] = -u[i];
    if (i > 0) dudt[i] += 0.1 * u[i - 1];
    if (i < n - 1) dudt[i] += 0.1 * u[i + 1];
  }
  return 0;
}

/* One integration over [0, 0.01] of n unknowns, banded when band >= 0 */
static int run(const char *scheme, int n, int band) {
  int status = -1, i;
  double *u;
  taylorode_t *ode = taylorode_create(scheme, n, &status);
  if (ode == NULL) {
    printf("%s n %d band %d: status %d: taylorode_create failed\n", scheme, n, band, status);
    return status;
  }
  u = malloc(sizeof(double) * (size_t)n);
  if (u == NULL) {
    printf("%s n %d band %d: the program's own state does not fit\n", scheme, n, band);
    taylorode_free(ode);
    return -1;
  }
  for (i = 0; i < n; i++) u[i] = 1.0;
  status = taylorode_set_functions(ode, NULL, chain, NULL, NULL, &n);
  if (status == TAYLORODE_OK && band >= 0) status = taylorode_set_bandwidths(ode, band, band);
  if (status == TAYLORODE_OK) status = taylorode_set_tolerances(ode, 1e-3, 1e-3);
  if (status == TAYLORODE_OK) status = taylorode_integrate(ode, 0.0, 0.01, u);
  printf("%s n %d band %d: status %d: %s\n", scheme, n, band, status, taylorode_message(ode));
  fflush(stdout);
  taylorode_free(ode);
  free(u);
  return status;
}

/* The peak address space of this process in kB (VmPeak), 0 when unknown */
static long peak_kb(void) {
  char line[256];
  long value = 0;
  FILE *file = fopen("/proc/self/status", "r");
  if (file == NULL) return 0;
  while (fgets(line, sizeof line, file) != NULL) {
    if (strncmp(line, "VmPeak:", 7) == 0) value = strtol(line + 7, NULL, 10);
  }
  fclose(file);
  return value;
}

int main(int argc, char **argv) {
  static const char *schemes[] = {"radau5", "i-t-2", "i-t-1", "si-t-2", "si-t-1", "imex-rk21"};
  size_t k;
  if (run("radau5", 1000, 1) != TAYLORODE_OK) return 1;
  if (argc > 1 && strcmp(argv[1], "measure") == 0) {
    printf("peak %ld\n", peak_kb());
    return 0;
  }
  for (k = 0; k < sizeof schemes / sizeof schemes[0]; k++) run(schemes[k], 50000, 200);
  run("radau5", 5000000, -1);
  return 0;
}

#endif
