#include "runtime/road/reference_line.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace sdv::road {
namespace {

// Natural cubic spline second derivatives for y(t) at knots t (Thomas algorithm).
std::vector<double> spline_m(const std::vector<double>& t, const std::vector<double>& y) {
    const size_t n = t.size();
    std::vector<double> m(n, 0.0);
    if (n < 3) return m;
    std::vector<double> a(n), b(n), c(n), r(n);
    for (size_t i = 1; i + 1 < n; ++i) {
        const double h0 = t[i] - t[i - 1], h1 = t[i + 1] - t[i];
        a[i] = h0;
        b[i] = 2 * (h0 + h1);
        c[i] = h1;
        r[i] = 6 * ((y[i + 1] - y[i]) / h1 - (y[i] - y[i - 1]) / h0);
    }
    for (size_t i = 2; i + 1 < n; ++i) {
        const double w = a[i] / b[i - 1];
        b[i] -= w * c[i - 1];
        r[i] -= w * r[i - 1];
    }
    for (size_t i = n - 2; i >= 1; --i) {
        m[i] = (r[i] - c[i] * m[i + 1]) / b[i];
        if (i == 1) break;
    }
    return m;
}

struct Spline1 {
    std::vector<double> t, y, m;
    // value, first and second derivative at u
    void eval(double u, double& v, double& d1, double& d2) const {
        size_t i = static_cast<size_t>(std::upper_bound(t.begin(), t.end(), u) - t.begin());
        i = std::clamp<size_t>(i, 1, t.size() - 1) - 1;
        const double h = t[i + 1] - t[i];
        const double A = (t[i + 1] - u) / h, B = (u - t[i]) / h;
        v = A * y[i] + B * y[i + 1] + ((A * A * A - A) * m[i] + (B * B * B - B) * m[i + 1]) * h * h / 6;
        d1 = (y[i + 1] - y[i]) / h + ((1 - 3 * A * A) * m[i] + (3 * B * B - 1) * m[i + 1]) * h / 6;
        d2 = A * m[i] + B * m[i + 1];
    }
};

double wrap(double a) {
    while (a > std::numbers::pi) a -= 2 * std::numbers::pi;
    while (a < -std::numbers::pi) a += 2 * std::numbers::pi;
    return a;
}

}  // namespace

std::optional<ReferenceLine> ReferenceLine::build(std::span<const Vec2> points, std::string* error,
                                                  double spacing) {
    auto fail = [&](const char* why) -> std::optional<ReferenceLine> {
        if (error != nullptr) *error = why;
        return std::nullopt;
    };
    std::vector<Vec2> pts;
    for (const Vec2& p : points) {
        if (!std::isfinite(p.x) || !std::isfinite(p.y)) return fail("non-finite coordinate");
        if (pts.empty() || distance(pts.back(), p) > 1e-3) pts.push_back(p);
    }
    if (pts.size() < 2) return fail("fewer than two distinct points");
    Spline1 sx, sy;
    double u = 0;
    for (size_t i = 0; i < pts.size(); ++i) {
        if (i > 0) u += distance(pts[i - 1], pts[i]);
        sx.t.push_back(u);
        sy.t.push_back(u);
        sx.y.push_back(pts[i].x);
        sy.y.push_back(pts[i].y);
    }
    if (!(u > 0) || !std::isfinite(u)) return fail("zero length");
    sx.m = spline_m(sx.t, sx.y);
    sy.m = spline_m(sy.t, sy.y);
    ReferenceLine line;
    const size_t n = std::max<size_t>(2, static_cast<size_t>(std::ceil(u / spacing)) + 1);
    double s = 0;
    double prev_theta = 0;
    Vec2 prev{};
    for (size_t i = 0; i < n; ++i) {
        const double ui = u * static_cast<double>(i) / static_cast<double>(n - 1);
        double x, dx, ddx, y, dy, ddy;
        sx.eval(ui, x, dx, ddx);
        sy.eval(ui, y, dy, ddy);
        if (i > 0) s += distance(prev, {x, y});
        prev = {x, y};
        const double speed2 = dx * dx + dy * dy;
        double theta = std::atan2(dy, dx);
        if (i > 0) theta = prev_theta + wrap(theta - prev_theta);  // unwrapped: interpolable
        prev_theta = theta;
        line.s_.push_back(s);
        line.x_.push_back(x);
        line.y_.push_back(y);
        line.theta_.push_back(theta);
        line.kappa_.push_back(speed2 > 0 ? (dx * ddy - dy * ddx) / std::pow(speed2, 1.5) : 0.0);
    }
    line.dkappa_.assign(n, 0.0);
    for (size_t i = 0; i + 1 < n; ++i) {
        const double ds = line.s_[i + 1] - line.s_[i];
        line.dkappa_[i] = ds > 0 ? (line.kappa_[i + 1] - line.kappa_[i]) / ds : 0.0;
    }
    line.dkappa_[n - 1] = line.dkappa_[n - 2];
    return line;
}

size_t ReferenceLine::segment(double s) const {
    auto it = std::upper_bound(s_.begin(), s_.end(), s);
    const auto i = static_cast<size_t>(it - s_.begin());
    return std::clamp<size_t>(i, 1, s_.size() - 1) - 1;
}

ReferenceLine::Interp ReferenceLine::at(double s) const {
    const size_t i = segment(s);
    const double ds = s_[i + 1] - s_[i];
    // Beyond the ends: straight extrapolation along the end tangent.
    if (s < s_.front() || s > s_.back()) {
        const size_t e = s < s_.front() ? 0 : s_.size() - 1;
        const double th = theta_[e];
        const double off = s - s_[e];
        return {{x_[e] + off * std::cos(th), y_[e] + off * std::sin(th)}, th, 0.0, 0.0};
    }
    const double f = ds > 0 ? (s - s_[i]) / ds : 0.0;
    Interp r;
    r.p = {x_[i] + f * (x_[i + 1] - x_[i]), y_[i] + f * (y_[i + 1] - y_[i])};
    r.theta = theta_[i] + f * (theta_[i + 1] - theta_[i]);
    r.kappa = kappa_[i] + f * (kappa_[i + 1] - kappa_[i]);
    r.dkappa = dkappa_[i];
    return r;
}

Vec2 ReferenceLine::point(double s) const { return at(s).p; }
double ReferenceLine::heading(double s) const { return at(s).theta; }
double ReferenceLine::curvature(double s) const { return at(s).kappa; }

FrenetState ReferenceLine::project(Vec2 p, double hint) const {
    // 1. the nearest sample (in a window around the hint, else globally);
    auto d2_at = [&](size_t i) {
        const double dx = p.x - x_[i], dy = p.y - y_[i];
        return dx * dx + dy * dy;
    };
    size_t centre = 0;
    if (hint >= 0) {
        centre = segment(hint);
    } else {
        // Coarse to fine: every 16th sample (4 m at the default spacing), then the neighbourhood.
        constexpr size_t kStride = 16;
        double best_coarse = INFINITY;
        for (size_t i = 0; i < s_.size(); i += kStride) {
            if (const double d2 = d2_at(i); d2 < best_coarse) {
                best_coarse = d2;
                centre = i;
            }
        }
        if (const double d2 = d2_at(s_.size() - 1); d2 < best_coarse) centre = s_.size() - 1;
    }
    constexpr size_t kWindow = 48;  // samples: 12 m at 0.25 m spacing
    const size_t lo = centre > kWindow ? centre - kWindow : 0;
    const size_t hi = std::min(s_.size() - 1, centre + kWindow);
    size_t best = lo;
    double best_d2 = INFINITY;
    for (size_t i = lo; i <= hi; ++i) {
        const double dx = p.x - x_[i], dy = p.y - y_[i];
        const double d2 = dx * dx + dy * dy;
        if (d2 < best_d2) {
            best_d2 = d2;
            best = i;
        }
    }
    // 2. solve g(s) = (p − P(s))·T(s) = 0 near it (Newton with bisection safeguard; g is
    //    decreasing in s near the curve).
    auto g = [&](double s) {
        const Interp r = at(s);
        return (p.x - r.p.x) * std::cos(r.theta) + (p.y - r.p.y) * std::sin(r.theta);
    };
    double a = best > 0 ? s_[best - 1] : s_.front() - 1e3;
    double b = best + 1 < s_.size() ? s_[best + 1] : s_.back() + 1e3;
    double ga = g(a), gb = g(b);
    double s = s_[best];
    if (ga >= 0 && gb <= 0) {
        for (int it = 0; it < 60 && b - a > 1e-12; ++it) {
            s = 0.5 * (a + b);
            const double gs = g(s);
            if (gs > 0) a = s;
            else b = s;
        }
        s = 0.5 * (a + b);
    } else {
        s = s_[best] + g(s_[best]);  // at a joint of the normal fan: closest sample's projection
    }
    const Interp r = at(s);
    FrenetState f;
    f.s = s;
    f.d = -(p.x - r.p.x) * std::sin(r.theta) + (p.y - r.p.y) * std::cos(r.theta);
    return f;
}

FrenetState ReferenceLine::to_frenet(const CartesianState& c, double hint) const {
    FrenetState f = project({c.x, c.y}, hint);
    const Interp r = at(f.s);
    const Vec2 T{std::cos(r.theta), std::sin(r.theta)}, N{-T.y, T.x};
    const double k = r.kappa, one = 1 - k * f.d;
    const Vec2 v{c.vx, c.vy}, a{c.ax, c.ay};
    f.d_d = dot(v, N);
    f.s_d = one != 0 ? dot(v, T) / one : 0.0;
    f.d_dd = dot(a, N) - k * f.s_d * f.s_d * one;
    f.s_dd = one != 0 ? (dot(a, T) + r.dkappa * f.s_d * f.s_d * f.d + 2 * k * f.s_d * f.d_d) / one : 0.0;
    return f;
}

CartesianState ReferenceLine::to_cartesian(const FrenetState& f) const {
    const Interp r = at(f.s);
    const Vec2 T{std::cos(r.theta), std::sin(r.theta)}, N{-T.y, T.x};
    const double k = r.kappa, one = 1 - k * f.d;
    const Vec2 p = r.p + f.d * N;
    const Vec2 v = (f.s_d * one) * T + f.d_d * N;
    const Vec2 a = (f.s_dd * one - r.dkappa * f.s_d * f.s_d * f.d - 2 * k * f.s_d * f.d_d) * T +
                   (k * f.s_d * f.s_d * one + f.d_dd) * N;
    return {p.x, v.x, a.x, p.y, v.y, a.y};
}

}  // namespace sdv::road
