// Scenario numbers in their fixed order, and variants applied through the bindings of a
// campaign (see bindings.h).
#include "runtime/ir/bindings.h"

#include <cmath>

namespace sdv::ir {
namespace {

template <typename P, typename F>
void each_position(P& p, F&& f) {
    f(p.s);
    f(p.offset);
    f(p.x);
    f(p.y);
    f(p.heading);
}

template <typename F>
void each_number(Program& program, int index, F&& f) {
    Scenario& s = program.scenarios[static_cast<size_t>(index)];
    f(s.timeout);
    f(s.traffic_rate);
    f(s.planning_rate);
    f(s.planning_latency);
    f(s.sensor_range);
    for (auto& v : s.vehicles) {
        f(v.length);
        f(v.width);
        f(v.speed);
        each_position(v.start, f);
        if (v.goal) each_position(*v.goal, f);
        for (auto& w : v.trajectory) {
            f(w.time);
            each_position(w.position, f);
            f(w.speed);
        }
    }
    for (auto& l : s.lights) {
        f(l.offset);
        for (auto& ph : l.phases) f(ph.duration);
    }
    for (auto& e : s.expects) {
        f(e.bound);
        if (e.after) f(*e.after);
        if (e.before) f(*e.before);
    }
    for (auto& v : s.vehicles) {
        if (v.tree < 0 || static_cast<size_t>(v.tree) >= program.instances.size()) continue;
        for (auto& n : program.instances[static_cast<size_t>(v.tree)].nodes) {
            for (auto& p : n.params) {
                f(p.number.value);
                f(p.number.lo);
                f(p.number.hi);
                f(p.number.sigma);
            }
        }
    }
}

}  // namespace

std::vector<double*> scenario_numbers(Program& program, int index) {
    std::vector<double*> out;
    each_number(program, index, [&](double& x) { out.push_back(&x); });
    return out;
}

std::vector<double> scenario_number_values(const Program& program, int index) {
    std::vector<double> out;
    each_number(const_cast<Program&>(program), index, [&](double& x) { out.push_back(x); });
    return out;
}

std::string apply_variant(Program& program, int index, const std::vector<double>& base,
                          const std::vector<double>& values) {
    Scenario& s = program.scenarios[static_cast<size_t>(index)];
    if (values.size() != s.vary.params.size()) return "a variant needs one value per varied parameter";
    auto numbers = scenario_numbers(program, index);
    if (numbers.size() != base.size()) return "the program's numbers do not match its base";
    for (size_t k = 0; k < values.size(); ++k) {
        const VaryParam& p = s.vary.params[k];
        const double v = values[k];
        if (!std::isfinite(v)) return "parameter '" + p.name + "' has no finite value";
        if (p.seed) {
            s.seed = static_cast<uint64_t>(std::llround(v));
            continue;
        }
        for (const auto& b : p.bindings) {
            if (b.number < 0 || static_cast<size_t>(b.number) >= numbers.size()) {
                return "parameter '" + p.name + "' binds number " + std::to_string(b.number) + ", out of range";
            }
            const auto i = static_cast<size_t>(b.number);
            *numbers[i] += b.scale * v + b.offset - base[i];
        }
    }
    return "";
}

void reset_variant(Program& program, int index, const Program& base) {
    Scenario& s = program.scenarios[static_cast<size_t>(index)];
    const Scenario& b = base.scenarios[static_cast<size_t>(index)];
    s.seed = b.seed;
    auto numbers = scenario_numbers(program, index);
    const auto values = scenario_number_values(base, index);
    for (const auto& p : s.vary.params) {
        for (const auto& bd : p.bindings) {
            const auto i = static_cast<size_t>(bd.number);
            if (i < numbers.size()) *numbers[i] = values[i];
        }
    }
}

}  // namespace sdv::ir
