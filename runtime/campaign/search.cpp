// Critical-scenario search with NLopt (see search.h).
#include "runtime/campaign/search.h"

#include <nlopt.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <map>

#include "runtime/campaign/variants.h"
#include "runtime/catalog/catalog.h"
#include "runtime/ir/bindings.h"
#include "runtime/sim/expectations.h"
#include "runtime/sim/road_cache.h"

namespace sdv::campaign {
namespace {

constexpr double kWorst = 1e9;       // the objective of a run that failed or measured nothing
constexpr double kGlobalShare = 0.6; // of the budget, for the global phase

std::string trim(const std::string& s) {
    size_t a = 0, b = s.size();
    while (a < b && std::isspace(static_cast<unsigned char>(s[a]))) ++a;
    while (b > a && std::isspace(static_cast<unsigned char>(s[b - 1]))) --b;
    return s.substr(a, b - a);
}

struct Search {
    const ir::Program& program;
    int scenario;
    const SearchOptions& o;
    VariantSpace space;
    std::vector<double> base;
    ir::Program variant;
    SearchResult result;
    std::map<std::vector<double>, double> seen;  // values → objective
    int budget_left = 0;
    nlopt_opt opt = nullptr;  // of the running phase

    Search(const ir::Program& p, int s, const SearchOptions& opts)
        : program(p), scenario(s), o(opts), space(p.scenarios[static_cast<size_t>(s)].vary),
          base(ir::scenario_number_values(p, s)), variant(p) {
        run_options.roads = std::make_shared<sim::RoadCache>();
    }

    sim::RunOptions run_options;  // every run shares the road

    // The objective NLopt minimises: the metric, negated to maximise; failures are worst.
    double objective(const double* u, unsigned n) {
        std::vector<double> values(n);
        for (unsigned k = 0; k < n; ++k) values[k] = space.at(k, u[k]);
        if (auto it = seen.find(values); it != seen.end()) return it->second;
        if (budget_left <= 0) {
            nlopt_force_stop(opt);
            return kWorst;
        }
        --budget_left;
        const ir::Scenario& sc = program.scenarios[static_cast<size_t>(scenario)];
        ir::reset_variant(variant, scenario, program);
        Evaluation ev;
        ev.values = values;
        std::string err = ir::apply_variant(variant, scenario, base, values);
        double f = kWorst;
        if (err.empty()) {
            const sim::RunResult r = sim::simulate(variant, scenario, run_options);
            err = r.error;
            if (err.empty()) {
                ev.metric = metric_value(sc, o.metric, r);
                const double signed_metric = o.maximize ? -ev.metric : ev.metric;
                f = std::isfinite(signed_metric) ? signed_metric : kWorst;
            }
        }
        ev.error = err;
        if (!err.empty()) ev.metric = o.maximize ? -INFINITY : INFINITY;
        result.runs.push_back(ev);
        const auto& best = result.runs[result.best];
        const bool better = best.error.empty() ? (err.empty() && (o.maximize ? ev.metric > best.metric : ev.metric < best.metric))
                                               : err.empty();
        if (result.runs.size() == 1 || better) result.best = result.runs.size() - 1;
        seen.emplace(values, f);
        if (o.progress) o.progress(static_cast<int>(result.runs.size()), o.budget, result.runs[result.best].metric);
        return f;
    }

    static double thunk(unsigned n, const double* x, double* grad, void* data) {
        (void)grad;  // derivative-free algorithms only
        return static_cast<Search*>(data)->objective(x, n);
    }

    // One NLopt phase from `x` with at most `evals` runs; keeps the best point in `x`.
    void phase(nlopt_algorithm algorithm, std::vector<double>& x, int evals) {
        const auto n = static_cast<unsigned>(x.size());
        if (algorithm == NLOPT_LN_BOBYQA && n < 2) algorithm = NLOPT_LN_SBPLX;  // BOBYQA needs two dimensions
        opt = nlopt_create(algorithm, n);
        if (opt == nullptr) return;
        std::vector<double> lo(n, 0.0), hi(n, 1.0);
        nlopt_set_lower_bounds(opt, lo.data());
        nlopt_set_upper_bounds(opt, hi.data());
        nlopt_set_min_objective(opt, &Search::thunk, this);
        // Revisits of a known variant cost no run, so allow NLopt more evaluations than runs.
        nlopt_set_maxeval(opt, std::max(1, evals) * 20);
        nlopt_set_xtol_abs1(opt, 1e-4);
        if (algorithm != NLOPT_GN_CRS2_LM) {
            std::vector<double> step(n, 0.1);
            nlopt_set_initial_step(opt, step.data());
        }
        budget_left = evals;
        double f = 0;
        nlopt_optimize(opt, x.data(), &f);  // a stop by maxeval or a roundoff limit is not an error
        nlopt_destroy(opt);
        opt = nullptr;
        budget_left = 0;
    }
};

}  // namespace

std::optional<Metric> parse_metric(const ir::Scenario& sc, const std::string& text, std::string& error) {
    const std::string t = trim(text);
    const auto open = t.find('('), close = t.rfind(')');
    if (open == std::string::npos || close == std::string::npos || close < open || close != t.size() - 1) {
        error = "'" + text + "' is not a metric: write it as an expectation names it, e.g. min_ttc(ego, v2)";
        return std::nullopt;
    }
    const std::string name = trim(t.substr(0, open));
    const auto* def = catalog::find_expectation(name);
    if (def == nullptr) {
        std::string list;
        for (const auto& e : catalog::expectations()) list += (list.empty() ? "" : ", ") + e.name;
        error = "unknown metric '" + name + "'; one of: " + list;
        return std::nullopt;
    }
    Metric m;
    m.function = static_cast<int32_t>(def->kind);
    m.boolean = def->boolean;
    m.unit = def->boolean ? "" : std::string(catalog::si_unit(def->result));
    std::string args = t.substr(open + 1, close - open - 1);
    size_t at = 0;
    while (!trim(args).empty() && at <= args.size()) {
        const size_t comma = args.find(',', at);
        const std::string word = trim(args.substr(at, comma == std::string::npos ? std::string::npos : comma - at));
        int32_t found = -1;
        for (size_t i = 0; i < sc.vehicles.size(); ++i) {
            if (sc.vehicles[i].name == word || (word == "ego" && sc.vehicles[i].is_ego)) found = static_cast<int32_t>(i);
        }
        if (found < 0) {
            error = "unknown vehicle '" + word + "' in metric '" + text + "' (scenario '" + sc.name + "')";
            return std::nullopt;
        }
        m.vehicles.push_back(found);
        if (comma == std::string::npos) break;
        at = comma + 1;
    }
    const int n = static_cast<int>(m.vehicles.size());
    if (n < def->min_vehicles || n > def->max_vehicles) {
        error = "'" + name + "' takes " + std::to_string(def->min_vehicles) +
                (def->max_vehicles != def->min_vehicles ? " to " + std::to_string(def->max_vehicles) : "") +
                " vehicle(s), found " + std::to_string(n);
        return std::nullopt;
    }
    m.text = name + "(";
    for (size_t i = 0; i < m.vehicles.size(); ++i) {
        m.text += (i ? ", " : "") + sc.vehicles[static_cast<size_t>(m.vehicles[i])].name;
    }
    m.text += ")";
    return m;
}

double metric_value(const ir::Scenario& sc, const Metric& m, const sim::RunResult& run) {
    // The metric as a one-call expectation of the scenario, evaluated like every other.
    ir::Scenario probe;
    probe.vehicles = sc.vehicles;
    ir::Expect e;
    e.kind = ir::Expect::Kind::call;
    e.function = m.function;
    e.vehicles = m.vehicles;
    e.cmp = m.boolean ? "" : "<";
    e.bound = INFINITY;
    e.text = m.text;
    probe.expects.push_back(e);
    probe.expect_roots.push_back(0);
    sim::RunResult r;
    r.events = run.events;
    r.pairs = run.pairs;
    r.vehicles = run.vehicles;
    r.timed_out = run.timed_out;
    r.duration = run.duration;
    sim::evaluate_expectations(probe, r);
    const auto& part = r.expectations.front().parts.front();
    if (m.boolean) return part.holds ? 1.0 : 0.0;
    if (part.value) return *part.value;
    const std::string& name = catalog::expectations()[static_cast<size_t>(m.function)].name;
    return name.rfind("max_", 0) == 0 ? -INFINITY : INFINITY;
}

SearchResult search(const ir::Program& program, int scenario, const SearchOptions& o) {
    Search s(program, scenario, o);
    const ir::Scenario& sc = program.scenarios[static_cast<size_t>(scenario)];
    if (sc.vary.empty()) {
        s.result.error = "scenario '" + sc.name + "' has no vary block: nothing to search";
        return std::move(s.result);
    }
    if (o.budget < 1) {
        s.result.error = "the budget must be at least one run";
        return std::move(s.result);
    }
    nlopt_srand(static_cast<unsigned long>(o.seed));
    std::vector<double> x(sc.vary.params.size(), 0.5);
    const int global = std::max(1, static_cast<int>(std::lround(o.budget * kGlobalShare)));
    s.phase(NLOPT_GN_CRS2_LM, x, global);
    // Refine from the best point found so far, with whatever the global phase left.
    const Evaluation& best = s.result.runs[s.result.best];
    for (size_t k = 0; k < x.size(); ++k) {
        // The coordinate of the best value: the middle of its level, or its place in its range.
        const auto levels = s.space.levels(k);
        if (!levels.empty()) {
            const auto it = std::find(levels.begin(), levels.end(), best.values[k]);
            x[k] = (static_cast<double>(it - levels.begin()) + 0.5) / static_cast<double>(levels.size());
        } else {
            double lo = 0, hi = 1;  // bisect at(): monotone in u
            for (int i = 0; i < 60; ++i) {
                const double mid = 0.5 * (lo + hi);
                (s.space.at(k, mid) < best.values[k] ? lo : hi) = mid;
            }
            x[k] = 0.5 * (lo + hi);
        }
    }
    const int left = o.budget - static_cast<int>(s.result.runs.size());
    if (left > 0) s.phase(NLOPT_LN_BOBYQA, x, left);
    return std::move(s.result);
}

}  // namespace sdv::campaign
