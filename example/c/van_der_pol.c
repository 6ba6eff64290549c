/* Van der Pol's equation from C: y' = z, z' = mu (1 - y^2) z - y with mu = 10, split as in
 * the paper (f = (z, -y) non-stiff, g = (0, mu (1 - y^2) z) stiff), integrated over [0, 10]
 * with i-t-2, first in one call, then in 100 calls that continue one another.
 * Build: make (uses pkg-config; set PKG_CONFIG_PATH to <prefix>/lib/pkgconfig). */
#include <stdio.h>
#include <taylorode.h>

static int f(double t, const double *u, double *dudt, void *data) {
  (void)t; (void)data;
  dudt[0] = u[1];
  dudt[1] = -u[0];
  return 0;
}

static int g(double t, const double *u, double *dudt, void *data) {
  const double mu = *(const double *)data;
  (void)t;
  dudt[0] = 0.0;
  dudt[1] = mu * (1.0 - u[0] * u[0]) * u[1];
  return 0;
}

static int jac_f(double t, const double *u, double *jac, void *data) {
  (void)t; (void)u; (void)data;
  jac[0] = 0.0; jac[1] = -1.0; /* column 1: d/dy */
  jac[2] = 1.0; jac[3] = 0.0;  /* column 2: d/dz */
  return 0;
}

static int jac_g(double t, const double *u, double *jac, void *data) {
  const double mu = *(const double *)data;
  (void)t;
  jac[0] = 0.0; jac[1] = -2.0 * mu * u[0] * u[1];
  jac[2] = 0.0; jac[3] = mu * (1.0 - u[0] * u[0]);
  return 0;
}

int main(void) {
  double mu = 10.0, u[2] = {2.0, 0.0};
  int status;
  taylorode_stats_t stats;
  taylorode_t *ode = taylorode_create("i-t-2", 2, &status);
  if (ode == NULL) {
    fprintf(stderr, "taylorode_create failed with status %d\n", status);
    return 1;
  }
  taylorode_set_functions(ode, f, g, jac_f, jac_g, &mu);
  taylorode_set_tolerances(ode, 1e-8, 1e-8);
  taylorode_set_option(ode, "autonomous", 1); /* f and g do not depend on t */
  status = taylorode_integrate(ode, 0.0, 10.0, u);
  if (status != TAYLORODE_OK) {
    fprintf(stderr, "taylorode_integrate: %s\n", taylorode_message(ode));
    taylorode_free(ode);
    return 1;
  }
  taylorode_get_stats(ode, &stats);
  printf("one call:   y = %.17e z = %.17e accepted %ld\n", u[0], u[1], stats.accepted_steps);

  u[0] = 2.0; u[1] = 0.0;
  status = taylorode_init(ode, 0.0, u);
  for (int k = 1; k <= 100 && status == TAYLORODE_OK; k++) status = taylorode_advance_to(ode, 0.1 * k, u);
  if (status != TAYLORODE_OK) {
    fprintf(stderr, "taylorode_advance_to: %s\n", taylorode_message(ode));
    taylorode_free(ode);
    return 1;
  }
  taylorode_get_stats(ode, &stats);
  printf("100 calls:  y = %.17e z = %.17e accepted %ld\n", u[0], u[1], stats.accepted_steps);
  taylorode_free(ode);
  return 0;
}
