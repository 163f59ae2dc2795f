/* Names of the public enums (names.h). */
#include "names.h"

#include <stdio.h>
#include <string.h>

static const char* const solvers[] = {"pcg", "jacobi", "chebyshev", "direct"};   /* weft_solver's order */
static const char* const preconds[] = {"default", "block_jacobi", "amg", "ic0"};  /* weft_preconditioner's */
static const char* const integrators[] = {"default", "be", "bdf2", "trbdf2"};     /* weft_integrator's */
static const char* const backends[] = {"auto", "cpu", "gpu"};                     /* weft_backend's */

#define COUNT(a) ((int)(sizeof(a) / sizeof((a)[0])))

static const char* name_of(const char* const* names, int n, int value) {
    return value >= 0 && value < n ? names[value] : "unknown";
}

/* first: the lowest value a name may give (1 skips "default") */
static int value_of(const char* const* names, int n, int first, const char* name) {
    for (int k = first; name && k < n; ++k)
        if (strcmp(name, names[k]) == 0) return k;
    return -1;
}

const char* cli_solver_name(weft_solver s) { return name_of(solvers, COUNT(solvers), (int)s); }
int cli_solver_from_name(const char* name) { return value_of(solvers, COUNT(solvers), 0, name); }
const char* cli_precond_name(weft_preconditioner p) { return name_of(preconds, COUNT(preconds), (int)p); }
int cli_precond_from_name(const char* name) { return value_of(preconds, COUNT(preconds), 1, name); }
const char* cli_integrator_name(weft_integrator i) { return name_of(integrators, COUNT(integrators), (int)i); }
int cli_integrator_from_name(const char* name) { return value_of(integrators, COUNT(integrators), 1, name); }
const char* cli_backend_name(weft_backend b) { return name_of(backends, COUNT(backends), (int)b); }
int cli_backend_from_name(const char* name) { return value_of(backends, COUNT(backends), 0, name); }

const char* cli_tolerance_text(double tolerance, char* buf, size_t len) {
    if (tolerance >= 0)
        snprintf(buf, len, "%g", tolerance);
    else
        snprintf(buf, len, "the library's (1e-3 on the CPU with backward Euler, its own preconditioner and "
                           "< 5,000 particles, 1e-4 otherwise)");
    return buf;
}
