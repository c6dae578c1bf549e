#include "runtime/io/plot.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <sstream>
#include <vector>

#include "runtime/io/run_dir.h"
#include "runtime/io/text.h"
#include "runtime/ir/ir_io.h"
#include "runtime/road/reader_text.h"

namespace sdv::io {
namespace {

struct Sample {
    double t, x, y, speed;
};

const char* kColours[] = {"#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b", "#e377c2", "#17becf"};

std::string f2(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.1f", v);
    return buf;
}

}  // namespace

std::string plot_run(const std::string& dir, std::string& error) {
    std::string road_text, csv;
    if (!road::read_file(dir + "/road.json", road_text) || !road::read_file(dir + "/trajectories.csv", csv)) {
        error = "'" + dir + "' is not a run directory (needs road.json and trajectories.csv; run it with sdv run -o)";
        return "";
    }
    if (ir::json_depth(road_text) > kMaxRunJsonDepth) {
        error = dir + "/road.json: JSON nested more than " + std::to_string(kMaxRunJsonDepth) + " levels deep";
        return "";
    }
    const auto road = nlohmann::json::parse(road_text, nullptr, false);
    if (road.is_discarded() || !road.is_object() || !road.contains("lanes") || !road["lanes"].is_array()) {
        error = "invalid road.json in '" + dir + "' (expected an object with an array of lanes)";
        return "";
    }
    std::map<std::string, std::vector<Sample>> paths;  // ordered by vehicle name
    std::map<std::string, bool> pedestrian;            // the `kind` column says so
    std::vector<std::string> order;
    TrajectoryReader in(csv, dir + "/trajectories.csv");
    TrajectoryRow r;
    while (in.next(r)) {
        const std::string name(r.vehicle);
        if (!paths.count(name)) order.push_back(name);
        pedestrian[name] = r.kind == "pedestrian";
        auto number = [](std::string_view t) { return std::strtod(std::string(t).c_str(), nullptr); };
        paths[name].push_back({number(r.time), number(r.x), number(r.y), number(r.speed)});
    }
    if (!in.error().empty()) {
        error = in.error();
        return "";
    }
    // Extent of the map panel: the vehicles' paths plus a margin (whole maps can be huge).
    double x0 = INFINITY, x1 = -INFINITY, y0 = INFINITY, y1 = -INFINITY, tmax = 1, vmax = 1;
    for (const auto& [name, ps] : paths) {
        for (const auto& p : ps) {
            x0 = std::min(x0, p.x), x1 = std::max(x1, p.x), y0 = std::min(y0, p.y), y1 = std::max(y1, p.y);
            tmax = std::max(tmax, p.t), vmax = std::max(vmax, std::fabs(p.speed));
        }
    }
    if (!std::isfinite(x0)) {
        error = "no trajectory rows in '" + dir + "'";
        return "";
    }
    const double margin = 15;
    x0 -= margin, x1 += margin, y0 -= margin, y1 += margin;
    const double W = 900, mapH = std::clamp(W * (y1 - y0) / (x1 - x0), 200.0, 600.0), plotH = 260, pad = 40;
    const double sx = (W - 2 * pad) / (x1 - x0), sy = (mapH - 2 * pad) / (y1 - y0), s = std::min(sx, sy);
    auto X = [&](double x) { return pad + (x - x0) * s; };
    auto Y = [&](double y) { return mapH - pad - (y - y0) * s; };
    std::ostringstream o;
    o << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << W << "\" height=\"" << mapH + plotH << "\" font-family=\"sans-serif\" font-size=\"11\">\n";
    o << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n<g id=\"road\" fill=\"none\">\n";
    auto poly = [&](const nlohmann::json& pts, const char* style) {
        if (!pts.is_array() || pts.size() < 2) return;
        o << "<polyline " << style << " points=\"";
        for (const auto& p : pts) {
            if (p.is_array() && p.size() == 2 && p[0].is_number() && p[1].is_number()) {
                const double px = p[0].get<double>(), py = p[1].get<double>();
                if (px < x0 - 50 || px > x1 + 50 || py < y0 - 50 || py > y1 + 50) continue;
                o << f2(X(px)) << "," << f2(Y(py)) << " ";
            }
        }
        o << "\"/>\n";
    };
    // Walkways and crosswalks (road.json has them only when the road does): closed outlines of
    // their two bounds, walkways light grey, crosswalks hatched.
    auto area = [&](const nlohmann::json& a, const char* style) {
        if (!a.is_object()) return;
        const auto left = a.value("left", nlohmann::json()), right = a.value("right", nlohmann::json());
        auto point = [](const nlohmann::json& p) { return p.is_array() && p.size() == 2 && p[0].is_number() && p[1].is_number(); };
        if (!left.is_array() || !right.is_array() || left.size() < 2 || right.size() < 2) return;
        if (!point(left.front()) || !point(left.back()) || !point(right.front()) || !point(right.back())) return;
        nlohmann::json ring = left;
        // Bounds may run either way: join the right one from the end nearest the left one's end.
        auto at = [](const nlohmann::json& p) { return std::pair{p[0].get<double>(), p[1].get<double>()}; };
        auto dist = [&](const nlohmann::json& p, const nlohmann::json& q) {
            const auto [ax, ay] = at(p);
            const auto [bx, by] = at(q);
            return std::hypot(ax - bx, ay - by);
        };
        const bool same = dist(left.back(), right.back()) <= dist(left.back(), right.front());
        for (size_t k = 0; k < right.size(); ++k) ring.push_back(right[same ? right.size() - 1 - k : k]);
        ring.push_back(left.front());
        poly(ring, style);
    };
    if (road.contains("walkways") && road["walkways"].is_array()) {
        for (const auto& w : road["walkways"]) area(w, "fill=\"#eeeff1\" stroke=\"#ccc\"");
    }
    for (const auto& l : road["lanes"]) {
        if (!l.is_object()) continue;
        poly(l.value("left", nlohmann::json()), "stroke=\"#bbb\"");
        poly(l.value("right", nlohmann::json()), "stroke=\"#bbb\"");
        poly(l.value("centre", nlohmann::json()), "stroke=\"#eee\" stroke-dasharray=\"4 4\"");
    }
    if (road.contains("crosswalks") && road["crosswalks"].is_array()) {
        o << "<defs><pattern id=\"zebra\" width=\"4\" height=\"4\" patternUnits=\"userSpaceOnUse\" patternTransform=\"rotate(45)\">"
             "<rect width=\"2\" height=\"4\" fill=\"#999\"/></pattern></defs>\n";
        for (const auto& c : road["crosswalks"]) area(c, "fill=\"url(#zebra)\" stroke=\"#999\"");
    }
    // Pedestrians' paths are dashed and labelled as pedestrians, here and in the speed plot.
    // The name is the text's own (what scripts read), the kind a tspan after it.
    auto label = [&](const std::string& name) {
        return xml_text(name) + (pedestrian[name] ? "<tspan font-style=\"italic\"> (pedestrian)</tspan>" : "");
    };
    auto dash = [&](const std::string& name) { return pedestrian[name] ? " stroke-dasharray=\"5 3\"" : ""; };
    o << "</g>\n<g id=\"paths\" fill=\"none\" stroke-width=\"2\">\n";
    for (size_t i = 0; i < order.size(); ++i) {
        const auto& ps = paths[order[i]];
        const char* c = kColours[i % 8];
        o << "<polyline stroke=\"" << c << "\"" << dash(order[i]) << " points=\"";
        for (size_t k = 0; k < ps.size(); k += 3) o << f2(X(ps[k].x)) << "," << f2(Y(ps[k].y)) << " ";
        o << "\"/>\n<circle cx=\"" << f2(X(ps.front().x)) << "\" cy=\"" << f2(Y(ps.front().y)) << "\" r=\"4\" fill=\"" << c << "\"/>\n";
        o << "<text x=\"" << f2(X(ps.back().x) + 5) << "\" y=\"" << f2(Y(ps.back().y) - 5) << "\" fill=\"" << c << "\" stroke=\"none\">" << label(order[i]) << "</text>\n";
    }
    o << "</g>\n";
    // Speed profiles.
    const double top = mapH + 20, h = plotH - 60, left = pad + 20, w = W - left - pad;
    o << "<g id=\"speeds\">\n<text x=\"" << left << "\" y=\"" << top - 5 << "\">speed (m/s) over time (s)</text>\n";
    o << "<rect x=\"" << left << "\" y=\"" << top << "\" width=\"" << w << "\" height=\"" << h << "\" fill=\"none\" stroke=\"#999\"/>\n";
    for (int k = 0; k <= 4; ++k) {
        const double v = vmax * k / 4, yy = top + h - h * k / 4;
        o << "<text x=\"" << left - 5 << "\" y=\"" << f2(yy + 4) << "\" text-anchor=\"end\">" << f2(v) << "</text>\n";
        const double t = tmax * k / 4, xx = left + w * k / 4;
        o << "<text x=\"" << f2(xx) << "\" y=\"" << f2(top + h + 15) << "\" text-anchor=\"middle\">" << f2(t) << "</text>\n";
    }
    for (size_t i = 0; i < order.size(); ++i) {
        const auto& ps = paths[order[i]];
        o << "<polyline fill=\"none\" stroke=\"" << kColours[i % 8] << "\" stroke-width=\"1.5\"" << dash(order[i]) << " points=\"";
        for (size_t k = 0; k < ps.size(); k += 3) {
            o << f2(left + w * ps[k].t / tmax) << "," << f2(top + h - h * std::fabs(ps[k].speed) / vmax) << " ";
        }
        // The legend inside the plot's top right corner (a pedestrian's label is long), on a halo.
        o << "\"/>\n<text x=\"" << f2(left + w - 6) << "\" y=\"" << f2(top + 14 + 14 * static_cast<double>(i))
          << "\" text-anchor=\"end\" stroke=\"white\" stroke-width=\"3\" paint-order=\"stroke\" fill=\"" << kColours[i % 8] << "\">"
          << label(order[i]) << "</text>\n";
    }
    o << "</g>\n</svg>\n";
    return o.str();
}

}  // namespace sdv::io
