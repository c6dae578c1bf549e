// Polynomials of degree ≤ 5 in time, as used for the s and d motion of a trajectory:
// quintic through (x, ẋ, ẍ) at 0 and T (the jerk-minimal curve), quartic when the end
// position is free (a velocity target). Evaluated with Horner's rule; derivatives analytically.
#pragma once

#include <array>

namespace sdv::planner {

class Poly {
public:
    Poly() = default;
    explicit Poly(std::array<double, 6> c) : c_(c) {}

    // Jerk-minimal quintic: x(0) = x0, ẋ(0) = v0, ẍ(0) = a0, x(T) = x1, ẋ(T) = v1, ẍ(T) = a1.
    static Poly quintic(double x0, double v0, double a0, double x1, double v1, double a1, double T);
    // Quartic with free end position: ẋ(T) = v1, ẍ(T) = a1.
    static Poly quartic(double x0, double v0, double a0, double v1, double a1, double T);
    // Constant acceleration from (x0, v0): x0 + v0 t + a t² / 2.
    static Poly quadratic(double x0, double v0, double a);

    double x(double t) const { return ((((c_[5] * t + c_[4]) * t + c_[3]) * t + c_[2]) * t + c_[1]) * t + c_[0]; }
    double v(double t) const { return (((5 * c_[5] * t + 4 * c_[4]) * t + 3 * c_[3]) * t + 2 * c_[2]) * t + c_[1]; }
    double a(double t) const { return ((20 * c_[5] * t + 12 * c_[4]) * t + 6 * c_[3]) * t + 2 * c_[2]; }
    double j(double t) const { return (60 * c_[5] * t + 24 * c_[4]) * t + 6 * c_[3]; }

    const std::array<double, 6>& coefficients() const { return c_; }

private:
    std::array<double, 6> c_{};  // c0 + c1 t + ... + c5 t⁵
};

}  // namespace sdv::planner
