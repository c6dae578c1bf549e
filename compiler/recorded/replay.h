// Recorded traffic as a scenario (docs/realism.md): the .sdv text that replays a recording on
// its road network, every agent following its recorded states, and optionally one vehicle
// replaced by an SDV with the recorded vehicle's start state, size and route (the paper's RQ2
// method). `sdv convert` writes it; `sdv replay` and `sdv calibrate` compile and run it.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "runtime/realism/recording.h"
#include "runtime/road/road_network.h"

namespace sdv::compiler::recorded {

struct ReplaySpec {
    std::string sdv;  // the id of the track an SDV replaces; empty: every agent as recorded
    // The SDV's tree call as written in a scenario; empty: std.drive at its start lane's speed
    // limit. `params` are appended to its arguments (name, value with unit), as a calibration
    // sets them.
    std::string tree;
    std::vector<std::pair<std::string, std::string>> params;
    std::vector<std::string> imports;  // files the tree comes from (std/drive.sdv is imported)
    double goal_beyond = 30;           // m past the last recorded position (realism::recorded_route)
};

struct ReplaySource {
    std::string text;
    std::string error;        // the track is unknown, or its path is on no lane
    std::string scenario;     // the scenario's name
    std::string sdv_name;     // the SDV's vehicle name (empty without one)
    double start = 0, end = 0;  // the SDV's recorded span (the whole recording without one)
};

// The scenario name of an agent: "v<id>" (or "p<id>" for a pedestrian), with every character
// that is not a letter, digit or '_' turned into '_'.
std::string agent_name(const realism::Track& track);

// `net` is the recording's road network (to find the SDV's route).
ReplaySource replay_source(const realism::Recording& recording, const road::RoadNetwork& net, const ReplaySpec& spec);

}  // namespace sdv::compiler::recorded
