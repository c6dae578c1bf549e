// The run outputs the simulation's observer writes while it runs (SPEC §7): the rows of
// trajectories.csv, decisions.jsonl (with --trace) and road.json (the road geometry and light
// programs of the run). The simulation itself writes nothing.
#pragma once

#include <sstream>
#include <string>

#include "runtime/sim/simulation.h"

namespace sdv::io {

struct Recording {
    std::string trajectories_csv;
    std::string decisions_jsonl;
    std::string road_json;
};

class Recorder : public sim::RunObserver {
public:
    void start(const sim::World& world) override;
    void tick(const sim::World& world, int tick, double time) override;
    void plan(const sim::World& world, const sim::Agent& agent) override;
    // The recording so far (the whole run once simulate returned).
    Recording take();

private:
    std::ostringstream csv_;
    std::string decisions_;
    std::string road_;
};

// The geometry a viewer needs, in metres, rounded to centimetres: lane centre lines and bounds
// (every ~1 m), stop lines, lights with the lanes they control and their programs.
std::string road_json(const sim::World& world);

// One planning cycle as a line of decisions.jsonl.
std::string decision_line(const sim::World& world, const sim::Agent& agent, const sim::PlanTrace& trace);

}  // namespace sdv::io
