// Closed-form solutions of the boundary-value problems (the 3×3 systems for the upper
// coefficients solved by hand), so that building a candidate costs a few multiplications.
#include "runtime/planner/polynomial.h"

namespace sdv::planner {

Poly Poly::quintic(double x0, double v0, double a0, double x1, double v1, double a1, double T) {
    const double T2 = T * T, T3 = T2 * T, T4 = T3 * T, T5 = T4 * T;
    const double c0 = x0, c1 = v0, c2 = 0.5 * a0;
    // Residuals of the end conditions after the known lower coefficients.
    const double h = x1 - (c0 + c1 * T + c2 * T2);
    const double dv = v1 - (c1 + 2 * c2 * T);
    const double da = a1 - 2 * c2;
    const double c3 = (10 * h - 4 * dv * T + 0.5 * da * T2) / T3;
    const double c4 = (-15 * h + 7 * dv * T - da * T2) / T4;
    const double c5 = (6 * h - 3 * dv * T + 0.5 * da * T2) / T5;
    return Poly({c0, c1, c2, c3, c4, c5});
}

Poly Poly::quartic(double x0, double v0, double a0, double v1, double a1, double T) {
    const double T2 = T * T, T3 = T2 * T;
    const double c0 = x0, c1 = v0, c2 = 0.5 * a0;
    const double dv = v1 - (c1 + 2 * c2 * T);
    const double da = a1 - 2 * c2;
    const double c3 = (3 * dv - da * T) / (3 * T2);
    const double c4 = (-2 * dv + da * T) / (4 * T3);
    return Poly({c0, c1, c2, c3, c4, 0.0});
}

Poly Poly::quadratic(double x0, double v0, double a) { return Poly({x0, v0, 0.5 * a, 0, 0, 0}); }

}  // namespace sdv::planner
