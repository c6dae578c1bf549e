// Recorded traffic: the tracks of real road users at fixed time steps, read from a CommonRoad
// XML scenario (its dynamic obstacles and traffic-light cycles; the lanelet network is read by
// road::load_commonroad) or from the INTERACTION dataset's track files (CSV, with a Lanelet2
// map in local metric coordinates given separately). docs/realism.md describes both formats as
// sdv reads them. Readers never throw; errors name the file's line and the element or column.
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace sdv::realism {

struct State {
    double t = 0;        // s from the recording's start
    double x = 0, y = 0; // centre, m
    double heading = 0;  // rad, counter-clockwise from +x
    double speed = 0;    // m/s
};

struct Track {
    std::string id;    // the recording's own id (CommonRoad obstacle id, INTERACTION track_id)
    std::string type;  // car, truck, bus, motorcycle, bicycle, pedestrian, ... as recorded
    double length = 4.5, width = 1.8;
    std::vector<State> states;  // in time order, at least one
    bool pedestrian() const { return type == "pedestrian" || type == "pedestrian/bicycle"; }
    double start() const { return states.front().t; }
    double end() const { return states.back().t; }
};

// A traffic light's cycle as recorded: phases in order (color, duration in s), repeated from
// `offset`.
struct LightCycle {
    std::string light;  // the network's name of the light (road::commonroad_light_name)
    std::vector<std::pair<std::string, double>> phases;
    double offset = 0;
};

struct Recording {
    std::string path;
    std::string format;    // "commonroad 2020a", "commonroad 2018b", "interaction"
    std::string map_path;  // the file of the road network (the CommonRoad file itself)
    double dt = 0.1;
    std::vector<Track> tracks;
    std::vector<LightCycle> lights;
    std::vector<std::string> errors, warnings;
    double duration() const;  // from the first state of any track to the last
    const Track* find(const std::string& id) const;
};

// The dynamic obstacles of a CommonRoad file (2018b `obstacle role="dynamic"`, 2020a
// `dynamicObstacle`) and its traffic-light cycles.
Recording read_commonroad(const std::string& path);
Recording parse_commonroad(const std::string& xml, const std::string& path = "<text>");

// An INTERACTION track file (vehicle_tracks_*.csv or pedestrian_tracks_*.csv); `map_path` is its
// Lanelet2 map (the dataset's maps are in local metres: nodes with local_x / local_y tags).
Recording read_interaction(const std::string& csv_path, const std::string& map_path);
Recording parse_interaction(const std::string& csv, const std::string& path = "<text>");

// Either format, by the file's content (a CommonRoad root element, or a CSV header).
Recording read_recording(const std::string& path, const std::string& map_path = "");

// Limits that keep reading linear and bounded: tracks per file, states per track.
inline constexpr size_t kMaxTracks = 100000;
inline constexpr size_t kMaxStates = 1000000;

}  // namespace sdv::realism
