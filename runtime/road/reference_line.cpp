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
    // The tridiagonal system's sub- and super-diagonals are the knot spacings: h(i) below, h(i + 1) above.
    auto h = [&](size_t i) { return t[i] - t[i - 1]; };
    std::vector<double> b(n), r(n);
    for (size_t i = 1; i + 1 < n; ++i) {
        const double h0 = h(i), h1 = h(i + 1);
        b[i] = 2 * (h0 + h1);
        r[i] = 6 * ((y[i + 1] - y[i]) / h1 - (y[i] - y[i - 1]) / h0);
    }
    for (size_t i = 2; i + 1 < n; ++i) {
        const double w = h(i) / b[i - 1];
        b[i] -= w * h(i);
        r[i] -= w * r[i - 1];
    }
    for (size_t i = n - 2; i >= 1; --i) {
        m[i] = (r[i] - h(i + 1) * m[i + 1]) / b[i];
        if (i == 1) break;
    }
    return m;
}

struct Spline1 {
    std::vector<double> t, y, m;
    // Value, first and second derivative at u. `below` counts the knots t <= u: the caller
    // keeps it between calls at increasing u, so that sampling the whole spline is linear.
    void eval(double u, size_t& below, double& v, double& d1, double& d2) const {
        while (below < t.size() && t[below] <= u) ++below;
        const size_t i = std::clamp<size_t>(below, 1, t.size() - 1) - 1;
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
    for (Spline1* sp : {&sx, &sy}) {
        sp->t.reserve(pts.size());
        sp->y.reserve(pts.size());
    }
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
    for (auto* v : {&line.s_, &line.x_, &line.y_, &line.theta_, &line.kappa_}) v->reserve(n);
    double s = 0;
    double prev_theta = 0;
    Vec2 prev{};
    size_t below_x = 0, below_y = 0;
    for (size_t i = 0; i < n; ++i) {
        const double ui = u * static_cast<double>(i) / static_cast<double>(n - 1);
        double x, dx, ddx, y, dy, ddy;
        sx.eval(ui, below_x, x, dx, ddx);
        sy.eval(ui, below_y, y, dy, ddy);
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
    for (size_t first = 0; first + 1 < n; first += kChunk) {
        Chunk c;
        c.first = first;
        c.last = std::min(n - 1, first + kChunk);
        c.min = c.max = {line.x_[first], line.y_[first]};
        for (size_t k = first; k <= c.last; ++k) {
            c.min = {std::min(c.min.x, line.x_[k]), std::min(c.min.y, line.y_[k])};
            c.max = {std::max(c.max.x, line.x_[k]), std::max(c.max.y, line.y_[k])};
        }
        line.chunks_.push_back(c);
    }
    double extent = 0;
    for (size_t k = 0; k < n; ++k) extent = std::max({extent, std::fabs(line.x_[k]), std::fabs(line.y_[k])});
    line.slack_ = 1e-9 * (1 + extent);
    for (size_t first = 0; first < line.chunks_.size(); first += kGroup) {
        Chunk g;
        g.first = first;
        g.last = std::min(line.chunks_.size(), first + kGroup);
        g.min = line.chunks_[first].min;
        g.max = line.chunks_[first].max;
        for (size_t k = first; k < g.last; ++k) {
            g.min = {std::min(g.min.x, line.chunks_[k].min.x), std::min(g.min.y, line.chunks_[k].min.y)};
            g.max = {std::max(g.max.x, line.chunks_[k].max.x), std::max(g.max.y, line.chunks_[k].max.y)};
        }
        line.groups_.push_back(g);
    }
    const double span = line.s_.back() - line.s_.front();
    line.per_metre_ = span > 0 ? static_cast<double>(n - 1) / span : 0.0;
    return line;
}

size_t ReferenceLine::segment(double s) const {
    // The last sample at or before s (clamped to a segment), as a binary search finds it. The
    // samples are nearly evenly spaced: start where even spacing puts s and walk the rest.
    const size_t n = s_.size();
    if (std::isnan(s)) return n - 2;
    if (!(s > s_.front())) return 0;
    if (s >= s_.back()) return n - 2;
    size_t i = std::min(n - 2, static_cast<size_t>((s - s_.front()) * per_metre_));
    while (i > 0 && s_[i] > s) --i;
    while (i + 2 < n && s_[i + 1] <= s) ++i;
    return i;
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

namespace {

// Squared distance from p to the segment [a, b], and the parameter of the foot in [0, 1].
double segment_d2(Vec2 p, Vec2 a, Vec2 b, double& t) {
    const double ex = b.x - a.x, ey = b.y - a.y;
    const double len2 = ex * ex + ey * ey;
    t = len2 > 0 ? std::clamp(((p.x - a.x) * ex + (p.y - a.y) * ey) / len2, 0.0, 1.0) : 0.0;
    const double dx = p.x - (a.x + t * ex), dy = p.y - (a.y + t * ey);
    return dx * dx + dy * dy;
}

}  // namespace

ReferenceLine::Foot ReferenceLine::nearest_in(Vec2 p, size_t first, size_t last) const {
    Foot best;
    for (size_t i = first; i < last; ++i) {
        double t = 0;
        const double d2 = segment_d2(p, {x_[i], y_[i]}, {x_[i + 1], y_[i + 1]}, t);
        if (d2 < best.d2) best = {i, t, d2};
    }
    return best;
}

namespace {

// Squared distance from p to a box (0 inside): no segment of the box's samples is nearer.
double box_d2(Vec2 p, Vec2 min, Vec2 max) {
    const double dx = std::max({min.x - p.x, 0.0, p.x - max.x});
    const double dy = std::max({min.y - p.y, 0.0, p.y - max.y});
    return dx * dx + dy * dy;
}

}  // namespace

ReferenceLine::Foot ReferenceLine::nearest_window(Vec2 p, size_t first, size_t last) const {
    // nearest_in keeps the first of equally near segments: the least (d2, segment). Taking that
    // least over the chunks in any order gives the same foot, so the chunk with the nearest box
    // goes first and another counts unless its box is farther than the best so far (a
    // pedestrian beside a lane scans one or two of a window's seven chunks). The box is widened
    // by far more than the rounding of the feet nearest_in computes, which may fall an ulp
    // outside it, and must be farther by more than the rounding of the squares.
    const size_t k0 = first / kChunk, k1 = (last + kChunk - 1) / kChunk;  // chunks k0..k1-1
    const Vec2 e{slack_, slack_};
    auto d2 = [&](size_t k) { return box_d2(p, chunks_[k].min - e, chunks_[k].max + e); };
    size_t start = k0;
    double start_d2 = INFINITY;
    for (size_t k = k0; k < k1; ++k) {
        if (const double d = d2(k); d < start_d2) {
            start_d2 = d;
            start = k;
        }
    }
    Foot best;
    auto scan = [&](size_t k) {
        const Foot f = nearest_in(p, std::max(first, chunks_[k].first), std::min(last, chunks_[k].last));
        if (f.d2 < best.d2 || (f.d2 == best.d2 && f.segment < best.segment)) best = f;
    };
    scan(start);
    for (size_t k = k0; k < k1; ++k) {
        if (k != start && !(d2(k) > best.d2 * (1 + 1e-9))) scan(k);
    }
    return best;
}

ReferenceLine::Foot ReferenceLine::nearest_global(Vec2 p) const {
    // Chunks of samples with bounding boxes: a chunk can hold the nearest point only if its box
    // is nearer than the best point found so far. Exact, and a few chunks are scanned in full.
    // A group's box is never farther than its chunks' (rounding is monotone), so a group is
    // passed over only where each of its chunks would be.
    auto box_d2 = [&](const Chunk& c) { return road::box_d2(p, c.min, c.max); };
    // 1. The start: the first chunk with the nearest box (0 when none is finitely near). Every
    // chunk that near is in a group no farther than a chunk of the nearest group.
    size_t nearest_group = 0;
    double group_d2 = INFINITY;
    for (size_t g = 0; g < groups_.size(); ++g) {
        if (const double d2 = box_d2(groups_[g]); d2 < group_d2) {
            group_d2 = d2;
            nearest_group = g;
        }
    }
    double bound = INFINITY;
    for (size_t k = groups_[nearest_group].first; k < groups_[nearest_group].last; ++k) {
        bound = std::min(bound, box_d2(chunks_[k]));
    }
    size_t start = 0;
    double start_d2 = INFINITY;
    for (const Chunk& g : groups_) {
        if (box_d2(g) > bound) continue;
        for (size_t k = g.first; k < g.last; ++k) {
            if (const double d2 = box_d2(chunks_[k]); d2 < start_d2) {
                start_d2 = d2;
                start = k;
            }
        }
    }
    // 2. From the start, every chunk whose box is nearer than the best point so far, in order.
    Foot best = nearest_in(p, chunks_[start].first, chunks_[start].last);
    for (const Chunk& g : groups_) {
        if (box_d2(g) >= best.d2) continue;
        for (size_t k = g.first; k < g.last; ++k) {
            if (k == start || box_d2(chunks_[k]) >= best.d2) continue;
            const Foot f = nearest_in(p, chunks_[k].first, chunks_[k].last);
            if (f.d2 < best.d2) best = f;
        }
    }
    return best;
}

FrenetState ReferenceLine::project(Vec2 p, double hint, double reach) const {
    // 1. The nearest point of the sampled polyline: near the hint when the hint's window holds a
    //    proper local minimum close to the line (continuity where a route comes back near
    //    itself), else over the whole line.
    const size_t segments = s_.size() - 1;
    Foot foot;
    bool found = false;
    if (hint >= 0 && std::isfinite(hint)) {
        constexpr size_t kWindow = 48;       // samples each side: 12 m at 0.25 m spacing
        const size_t centre = segment(hint);
        const size_t lo = centre > kWindow ? centre - kWindow : 0;
        const size_t hi = std::min(segments, centre + kWindow + 1);
        foot = nearest_window(p, lo, hi);
        const bool at_low_edge = foot.segment == lo && foot.t == 0.0 && lo > 0;
        const bool at_high_edge = foot.segment + 1 == hi && foot.t == 1.0 && hi < segments;
        found = !at_low_edge && !at_high_edge && foot.d2 <= reach * reach;  // else globally
    }
    if (!found) foot = nearest_global(p);
    // 2. Solve g(s) = (p − P(s))·T(s) = 0 near that point, on the same interpolation that
    //    to_cartesian uses (so that round trips are exact): bisection on a bracket where g goes
    //    from positive to negative, widened a few segments at a time.
    auto g = [&](double s) {
        const Interp r = at(s);
        return (p.x - r.p.x) * std::cos(r.theta) + (p.y - r.p.y) * std::sin(r.theta);
    };
    const size_t i = foot.segment;
    double s = s_[i] + foot.t * (s_[i + 1] - s_[i]);
    bool solved = false;
    for (size_t widen = 1; widen <= 4 && !solved; widen *= 2) {
        const size_t ia = i > widen - 1 ? i - (widen - 1) : 0;
        const size_t ib = std::min(segments, i + widen);
        double a = s_[ia], b = s_[ib];
        // Beyond the ends the line continues straight along its end tangents.
        if (ia == 0 && g(a) < 0) a = s_.front() - 1e4;
        if (ib == segments && g(b) > 0) b = s_.back() + 1e4;
        double ga = g(a), gb = g(b);
        if (!(ga >= 0 && gb <= 0)) continue;
        // Regula falsi with the Illinois rule: g is nearly linear on a bracket this small, so a
        // few steps reach 1e-10 m; bisection guards against a slow side.
        int side = 0;
        for (int it = 0; it < 100 && b - a > 1e-10; ++it) {
            double m = ga - gb > 0 ? a + ga * (b - a) / (ga - gb) : 0.5 * (a + b);
            if (!(m > a && m < b) || it % 8 == 7) m = 0.5 * (a + b);
            const double gm = g(m);
            if (gm == 0) {
                a = b = m;
                break;
            }
            if (gm > 0) {
                a = m;
                ga = gm;
                if (side == -1) gb *= 0.5;
                side = -1;
            } else {
                b = m;
                gb = gm;
                if (side == 1) ga *= 0.5;
                side = 1;
            }
            if (std::fabs(gm) < 1e-12) {
                a = b = m;
                break;
            }
        }
        s = 0.5 * (a + b);
        solved = true;
    }
    // Unsolved (p beyond the centre of curvature of a tight bend): the polyline's nearest point.
    const Interp r = at(s);
    FrenetState f;
    f.s = s;
    f.d = -(p.x - r.p.x) * std::sin(r.theta) + (p.y - r.p.y) * std::cos(r.theta);
    return f;
}

FrenetState ReferenceLine::to_frenet(const CartesianState& c, double hint, double reach) const {
    FrenetState f = project({c.x, c.y}, hint, reach);
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
