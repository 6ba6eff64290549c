"""Van der Pol's equation from Python through the C interface (ctypes and numpy):
y' = z, z' = mu (1 - y^2) z - y with mu = 10, the paper's splitting, i-t-2 over [0, 10].

    make install PREFIX=<prefix>
    TAYLORODE_PREFIX=<prefix> python3 example/python/van_der_pol.py

Prints the final state with 17 digits (the same numbers as the Fortran and C versions).
"""
import ctypes
import os
import sys

import numpy as np

prefix = os.environ.get("TAYLORODE_PREFIX", os.path.join(os.path.dirname(__file__), "..", "..", "build", "install"))
lib = ctypes.CDLL(os.path.join(prefix, "lib", "libtaylorode.so"))

double_p = ctypes.POINTER(ctypes.c_double)
RHS = ctypes.CFUNCTYPE(ctypes.c_int, ctypes.c_double, double_p, double_p, ctypes.c_void_p)
lib.taylorode_create.restype = ctypes.c_void_p
lib.taylorode_create.argtypes = [ctypes.c_char_p, ctypes.c_int, ctypes.POINTER(ctypes.c_int)]
lib.taylorode_set_functions.argtypes = [ctypes.c_void_p, RHS, RHS, RHS, RHS, ctypes.c_void_p]
lib.taylorode_set_tolerances.argtypes = [ctypes.c_void_p, ctypes.c_double, ctypes.c_double]
lib.taylorode_set_option.argtypes = [ctypes.c_void_p, ctypes.c_char_p, ctypes.c_double]
lib.taylorode_integrate.argtypes = [ctypes.c_void_p, ctypes.c_double, ctypes.c_double, double_p]
lib.taylorode_message.restype = ctypes.c_char_p
lib.taylorode_message.argtypes = [ctypes.c_void_p]
lib.taylorode_free.argtypes = [ctypes.c_void_p]

MU = 10.0
failures = []


def callback(function):
    """A C callback that stops the integration (returns -1) when the Python function raises:
    ctypes itself would print the exception and return 0, and the library would go on with
    the values never written (status ok with a wrong answer)."""

    def guarded(*args):
        try:
            return function(*args)
        except BaseException as exception:
            failures.append(exception)
            return -1

    return RHS(guarded)


def view(pointer, count):
    """A numpy array on memory the library owns (no copy)."""
    return np.ctypeslib.as_array(pointer, shape=(count,))


@callback
def f(t, u, dudt, data):
    u, dudt = view(u, 2), view(dudt, 2)
    dudt[0] = u[1]
    dudt[1] = -u[0]
    return 0


@callback
def g(t, u, dudt, data):
    u, dudt = view(u, 2), view(dudt, 2)
    dudt[0] = 0.0
    dudt[1] = MU * (1.0 - u[0] * u[0]) * u[1]
    return 0


@callback
def jac_f(t, u, jac, data):
    view(jac, 4)[:] = [0.0, -1.0, 1.0, 0.0]  # column-major
    return 0


@callback
def jac_g(t, u, jac, data):
    u = view(u, 2)
    view(jac, 4)[:] = [0.0, -2.0 * MU * u[0] * u[1], 0.0, MU * (1.0 - u[0] * u[0])]
    return 0


status = ctypes.c_int()
ode = lib.taylorode_create(b"i-t-2", 2, ctypes.byref(status))
if not ode:
    sys.exit(f"taylorode_create failed with status {status.value}")
lib.taylorode_set_functions(ode, f, g, jac_f, jac_g, None)
lib.taylorode_set_tolerances(ode, 1e-8, 1e-8)
lib.taylorode_set_option(ode, b"autonomous", 1.0)  # f and g do not depend on t
u = np.array([2.0, 0.0])
code = lib.taylorode_integrate(ode, 0.0, 10.0, u.ctypes.data_as(double_p))
if failures:
    lib.taylorode_free(ode)
    raise failures[0]
if code != 0:
    message = lib.taylorode_message(ode).decode()
    lib.taylorode_free(ode)
    sys.exit(f"taylorode_integrate: {message}")
lib.taylorode_free(ode)
print(f"y = {u[0]:.17e} z = {u[1]:.17e}")
