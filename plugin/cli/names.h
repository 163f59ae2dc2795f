/* The names the tool gives the public enums, on the command line, in scene files and in its
 * outputs: solvers "pcg" "jacobi" "chebyshev" "direct", preconditioners "block_jacobi" "amg" "ic0",
 * integrators "be" "bdf2" "trbdf2", backends "auto" "cpu" "gpu". A *_from_name returns the
 * weft.h value, or -1 for a name that is not one of those ("default" included: callers that take
 * it handle it themselves). */
#ifndef WEFT_CLI_NAMES_H
#define WEFT_CLI_NAMES_H
#include "weft/weft.h"

const char* cli_solver_name(weft_solver s);
int cli_solver_from_name(const char* name);
/* BLOCK_JACOBI "block_jacobi", AMG "amg", IC0 "ic0", DEFAULT "default". */
const char* cli_precond_name(weft_preconditioner p);
int cli_precond_from_name(const char* name);
/* BACKWARD_EULER "be", BDF2 "bdf2", TRBDF2 "trbdf2", DEFAULT "default". */
const char* cli_integrator_name(weft_integrator i);
int cli_integrator_from_name(const char* name);
const char* cli_backend_name(weft_backend b);
int cli_backend_from_name(const char* name);
/* weft_cloth_def.tolerance for a report: "%g", or for -1 what the library makes of it. */
const char* cli_tolerance_text(double tolerance, char* buf, size_t len);

#endif
