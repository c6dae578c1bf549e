// stop_for_light: a driver's stop-or-go decision at a red or yellow light (docs/catalog.md).
//
// A driver that meets a light turning yellow (or first sees it red) stops if its front bumper
// can come to rest at the stop line at no more than `decel` (v² / 2·gap, from the state at the
// plan's start), and otherwise goes on: a driver close to the line at speed cannot stop in time
// and would only brake hard and stop in the junction. The stop decision is kept until the light
// is green again (while braking along a quintic the constant deceleration still needed grows,
// and a decision read afresh would flip to go half way); a go decision is read afresh each time,
// so a driver that slows before the line (behind a queue) stops for it once it can.
#include <algorithm>
#include <cmath>

#include "runtime/sim/leaves.h"

namespace sdv::sim {

bool stop_for_light(Leaves& l, const ir::Node& n, int32_t) {
    Driver& d = *l.a.driver;
    const double self_s = l.view.self.s;
    const double front = self_s + 0.5 * l.a.v->length;
    const double look = l.num(n, "distance");
    for (size_t i = 0; i < d.path.size(); ++i) {
        const auto& ln = l.w.net.lane(d.path[i]);
        const double start = d.path_start[i];
        if (start > self_s + look) break;
        // The next line the front bumper has not passed by more than half a metre (a stop puts
        // it on the line), as traffic_light finds it.
        const road::StopLine* line = ln.stop_line_from(self_s - 0.5 - start);
        if (line == nullptr || start + line->s > self_s + look) continue;
        if (line->traffic_lights.empty()) continue;  // the next stop line has no light
        if (l.w.light_state(line->traffic_lights.front(), l.t0) == "green") break;
        if (d.light_stop == line) return true;
        const double gap = start + line->s - front;
        if (gap < -0.5) break;
        const double v = std::max(0.0, l.view.self.s_d);
        const bool can_stop = v * v <= 2 * l.num(n, "decel") * std::max(gap, 0.0) || v < 0.5;
        d.light_stop = can_stop ? line : nullptr;
        return can_stop;
    }
    d.light_stop = nullptr;
    return false;
}

}  // namespace sdv::sim
