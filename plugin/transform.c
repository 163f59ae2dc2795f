/* Host transforms: 16 floats, column-major (element (row r, column c) at m[4c + r]). The check
 * gates what hosts may pass (finite, rotation + translation); core's maths (core/xform.h) then
 * uses the matrix as given. */
#include <math.h>
#include <stdio.h>
#include "api_internal.h"

weft_status wa_check_transform(const float* m, char* why, size_t why_size) {
    for (int k = 0; k < 16; ++k)
        if (!isfinite(m[k])) {
            snprintf(why, why_size, "[%d] is %s", k, isnan(m[k]) ? "NaN" : "Inf");
            return WEFT_ERROR_NONFINITE;
        }
    /* last row: elements (3, c) at m[4c + 3] */
    if (fabsf(m[3]) > 1e-6f || fabsf(m[7]) > 1e-6f || fabsf(m[11]) > 1e-6f || fabsf(m[15] - 1.0f) > 1e-6f) {
        snprintf(why, why_size, " has last row (%g, %g, %g, %g), not (0, 0, 0, 1)", (double)m[3], (double)m[7],
                 (double)m[11], (double)m[15]);
        return WEFT_ERROR_INVALID_ARGUMENT;
    }
    wc_xform x;
    wc_xform_from_floats(&x, m);
    const double* R = x.R;
    double det = R[0] * (R[4] * R[8] - R[5] * R[7]) - R[1] * (R[3] * R[8] - R[5] * R[6]) +
                 R[2] * (R[3] * R[7] - R[4] * R[6]);
    double worst = 0.0;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            double d = R[i] * R[j] + R[3 + i] * R[3 + j] + R[6 + i] * R[6 + j] - (i == j ? 1.0 : 0.0);
            if (fabs(d) > worst) worst = fabs(d);
        }
    if (!(fabs(det - 1.0) < 1e-3) || !(worst < 1e-3)) {
        snprintf(why, why_size,
                 " is not rigid (det %.6g, max |R^T R - I| %.3g; tolerance 1e-3): scale the mesh instead", det, worst);
        return WEFT_ERROR_INVALID_ARGUMENT;
    }
    return WEFT_OK;
}
