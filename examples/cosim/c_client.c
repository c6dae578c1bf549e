/* Drives the external ego of examples/cosim/cut_in.sdv through the C API (docs/cosim.md): the
 * ego follows the car ahead in its lane (IDM) and steers back to its lane's centre; sdv moves
 * everyone else.
 *   cc -std=c99 c_client.c -I<sdv>/include -L<sdv>/build/dev -lsdv -lm -o c_client
 *   ./c_client examples/cosim/cut_in.sdv out/c_client */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "sdv/sdv.h"

int main(int argc, char** argv) {
    sdv_config cfg = {sizeof cfg, argc > 1 ? argv[1] : "examples/cosim/cut_in.sdv", NULL,
                      argc > 2 ? argv[2] : NULL, 0, 0, 0, 0, 1};
    sdv_sim* sim = NULL;
    uint64_t ego;
    if (sdv_create(&cfg, &sim) != SDV_OK || sdv_claim(sim, "ego", SDV_CONTROL_POSE, &ego) != SDV_OK) {
        fprintf(stderr, "%s\n", sdv_last_error(sim));
        sdv_destroy(sim);
        return 1;
    }
    sdv_actor_state all[64], me;
    size_t n = 0, m = 0;
    sdv_run_state rs = SDV_RUNNING;
    double last_d = 0, dt = 1.0 / 30;
    while (rs == SDV_RUNNING) {
        if (sdv_get_actor_states(sim, all, 64, &n) != SDV_OK) break;
        me = all[ego - 1]; /* ids are positions + 1, sorted */
        /* Lane keeping: a yaw rate against the offset and its rate (left of centre is d > 0). */
        double yaw_rate = -0.4 * me.d - 1.2 * (me.d - last_d) / dt;
        last_d = me.d;
        me.yaw += yaw_rate * dt;
        me.x += me.speed * cos(me.yaw) * dt;
        me.y += me.speed * sin(me.yaw) * dt;
        /* IDM towards 13.9 m/s behind the nearest car ahead in the same lane (4.5 m long cars). */
        double gap = 1e9, dv = 0;
        for (size_t i = 0; i < n; ++i)
            if (all[i].id != ego && !strcmp(all[i].lane_id, me.lane_id) && all[i].s > me.s && all[i].s - me.s - 4.5 < gap) {
                gap = all[i].s - me.s - 4.5;
                dv = me.speed - all[i].speed;
            }
        double want = 2 + me.speed * 1.5 + me.speed * dv / (2 * sqrt(2.0 * 3.0));
        me.accel = 2.0 * (1 - pow(me.speed / 13.9, 4) - pow((want > 0 ? want : 0) / (gap > 0.1 ? gap : 0.1), 2));
        if (me.accel < -8) me.accel = -8;
        me.speed = me.speed + me.accel * dt > 0 ? me.speed + me.accel * dt : 0;
        if (sdv_set_external_state(sim, &me) != SDV_OK || sdv_step(sim, &rs) != SDV_OK) break;
        sdv_event ev[16];
        if (sdv_poll_events(sim, ev, 16, &m) == SDV_OK)
            for (size_t i = 0; i < m; ++i)
                if (ev[i].type == SDV_EVENT_COLLISION) printf("collision at tick %llu\n", (unsigned long long)ev[i].tick);
    }
    int32_t passed = 0;
    int ok = sdv_finish(sim) == SDV_OK && sdv_passed(sim, &passed) == SDV_OK;
    printf("%s (run state %d, expectations %s)\n", ok ? "finished" : sdv_last_error(sim), (int)rs, passed ? "hold" : "fail");
    sdv_destroy(sim);
    return ok && passed ? 0 : 1;
}
