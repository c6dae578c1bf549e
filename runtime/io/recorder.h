// The run outputs the simulation's observer writes while it runs (SPEC §7): the rows of
// trajectories.csv, decisions.jsonl (with --trace) and road.json (the road geometry and light
// programs of the run). The simulation itself writes nothing. Rows go to streams as the run
// goes (files in the output directory for `sdv run`), so memory does not grow with the run.
#pragma once

#include <fstream>
#include <memory>
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
    // Records in memory (take() returns it all).
    Recorder();
    // Streams trajectories.csv (and decisions.jsonl when `trace`) into `dir`, under temporary
    // names until commit(). Returns an error message, or "" when the files are open.
    std::string open(const std::string& dir, bool trace);
    // Flushes and gives the streamed files their names; an error message or "".
    std::string commit();
    // Removes the streamed files (a run that failed leaves no partial outputs).
    void discard();
    ~Recorder() override;

    void start(const sim::World& world) override;
    void tick(const sim::World& world, int tick, double time) override;
    void plan(const sim::World& world, const sim::Agent& agent) override;
    // The recording so far (the whole run once simulate returned); a streamed recording holds
    // only road.json here.
    Recording take();

private:
    struct File {
        std::string path;  // final name; written at path + ".part"
        std::ofstream out;
    };
    std::ostream* csv_ = nullptr;
    std::ostream* decisions_ = nullptr;
    std::ostringstream csv_memory_, decisions_memory_;
    std::unique_ptr<File> csv_file_, decisions_file_;
    std::string road_;
};

// The geometry a viewer needs, in metres, rounded to centimetres: lane centre lines and bounds
// (every ~1 m), stop lines, lights with the lanes they control and their programs; when the
// road has them, crosswalks (centre, bounds, width, the pedestrians' light and whether it is
// the vehicles' one inverted) and walkways (bounds).
std::string road_json(const sim::World& world);

// One planning cycle as a line of decisions.jsonl.
std::string decision_line(const sim::World& world, const sim::Agent& agent, const sim::PlanTrace& trace);
// One line of decisions.jsonl for a pedestrian's tree tick (its nodes, maneuver and intent).
std::string walker_line(const sim::World& world, const sim::Agent& agent);

}  // namespace sdv::io
