#include "runtime/sim/progress.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "runtime/catalog/catalog.h"

namespace sdv::sim {
namespace {

constexpr double kCrawl = 0.5;       // m/s
constexpr double kQueueReach = 15.0;  // m between centres: someone slow this close ahead
constexpr double kLongestVehicle = 60.0;  // m: half of it bounds how far a vehicle's centre is from its rear

bool waiting(const World& w, const Agent& a) {
    if (a.crashed) return true;
    const Driver& d = *a.driver;
    if (d.maneuver >= 0) {
        // The tree chose to stand: a stop, or keeping a speed of (almost) zero (parked).
        const ir::Node& n = d.tree->instance().nodes[static_cast<size_t>(d.maneuver)];
        const auto kind = static_cast<catalog::ManeuverKind>(n.leaf);
        if (kind == catalog::ManeuverKind::stop) return true;
        if (kind == catalog::ManeuverKind::keep_velocity) {
            const auto& defs = catalog::maneuver(kind).params;
            for (size_t i = 0; i < defs.size() && i < n.params.size(); ++i) {
                if (defs[i].field == catalog::ConfigField::speed && n.params[i].given && n.params[i].number.value < kCrawl) return true;
            }
        }
    }
    // A queue: someone standing or crawling just ahead, in the way along its heading.
    const double c = std::cos(a.yaw), s = std::sin(a.yaw);
    // Candidates from the snapshot's grid (taken this tick, before this check).
    thread_local std::vector<int> near;
    w.grid.query(a.x, a.y, kQueueReach + 0.5 * a.v->length + kLongestVehicle, near);
    for (const int k : near) {
        const Agent& o = w.agents[static_cast<size_t>(k)];
        if (&o == &a || !o.active || std::fabs(o.speed) >= kCrawl) continue;
        const double dx = o.x - a.x, dy = o.y - a.y;
        const double lon = dx * c + dy * s, lat = std::fabs(-dx * s + dy * c);
        if (lon > 0 && lon < kQueueReach + 0.5 * (o.v->length + a.v->length) && lat < 0.5 * (o.v->width + a.v->width) + 1.0) return true;
    }
    return false;
}

}  // namespace

void ProgressMonitor::observe(const World& w, double t, RunResult& out) {
    for (size_t i = 0; i < w.agents.size(); ++i) {
        const Agent& a = w.agents[i];
        if (!a.driver || !a.active) continue;
        if (std::fabs(a.speed) >= kCrawl || waiting(w, a)) {
            since_[i] = -1;
            continue;
        }
        if (since_[i] < 0) since_[i] = t;
        auto& vm = out.vehicles[i];
        vm.longest_stall_s = std::max(vm.longest_stall_s, t - since_[i]);
    }
}

}  // namespace sdv::sim
