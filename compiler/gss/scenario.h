// The GeoScenario 2.0 front end: reads a scenario (.gs.osm, OSM XML; SPEC §8) into a plain
// description, validates it (every problem is an error naming the element, at its line), and
// converts it, with the .btree trees it uses (gss/lower.h), into .sdv source text. `sdv run`
// compiles that text like any .sdv file; `sdv convert` writes it out.
#pragma once

#include <array>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "compiler/diag/diagnostic_engine.h"
#include "compiler/diag/source_manager.h"

namespace sdv::compiler::gss {

struct GeoPoint {
    double lat = 0, lon = 0;
    diag::SourceRange range;
};

struct GsVehicle {
    int vid = 0;
    std::string name;
    std::string btype;  // SDV, TV, PV, EV; NV: neutral (no or another btype), motionless
    std::string btree;  // .btree file name (SDV)
    std::string route;  // route name (SDV)
    std::string trajectory;  // trajectory name (TV)
    std::string path;        // path name (PV)
    bool use_speed_profile = false;  // PV: usespeedprofile=yes
    std::optional<int> meet;         // PV: collision_vehicle_vid, the vehicle it is timed to meet
    double speed = 0;        // SDV, EV: m/s as written; PV: km/h (the reference divides by 3.6)
    bool has_speed = false;
    double length = 4.5, width = 1.8;
    bool goal_ends_simulation = false;
    std::optional<double> yaw;  // degrees, clockwise: the heading is -yaw
    bool default_btree = false;  // SDV without btree: the reference's st_standard_driver.btree
    std::string btconfig;        // SDV: overrides of its tree's nodes ("NODE=MConfig(...);...")
    std::optional<double> start_speed;  // SDV: from start_cartesian or start_frenet (else at rest)
    bool start_frenet = false;          // SDV: start at frenet_s, frenet_d on its route's first lanelet
    double frenet_s = 0, frenet_d = 0;
    GeoPoint at;
    diag::SourceRange range;
};

struct GsTnode {
    GeoPoint at;
    double time = 0;
    std::optional<double> speed;
};

// A node of a `path` way (PV, PP): where, and the reference's speed profile tags.
struct GsPathNode {
    GeoPoint at;
    std::optional<double> speed;  // agentspeed, km/h
    bool accel = false;           // agentacceleration or timetoacceleration given
};

// A pedestrian (gs=pedestrian): btype TP (trajectory), SP (simulated, with a behavior tree) or
// PP (path; the reference's default).
struct GsPedestrian {
    int pid = 0;
    std::string name;
    std::string btype;        // TP, SP, PP
    std::string btree;        // SP: .btree file name (default walk.btree)
    std::string route;        // SP: its last node is the goal
    std::string destination;  // SP: a location node, the goal (without route)
    std::string trajectory;   // TP
    std::string path;         // PP
    std::optional<double> speed;  // PP: km/h (an SP's is not read: has_speed says it was given)
    std::optional<int> meet;      // PP: collision_vehicle_vid
    bool has_speed = false;
    bool use_speed_profile = false;
    double length = 0.6, width = 0.5;  // the reference's PEDESTRIAN_LENGTH, PEDESTRIAN_WIDTH
    GeoPoint at;
    diag::SourceRange range, btree_range;
};

struct GsLight {
    std::string name;
    std::vector<std::string> states;     // G, Y, R
    std::vector<double> durations;       // s
    diag::SourceRange range;
};

struct GsObject {
    std::string name;
    GeoPoint at;
    double length = 0.5, width = 0.5;  // GeoScenario objects are points: a 0.5 m square
    std::optional<std::array<double, 4>> area;  // a way: its extent (lat0, lon0, lat1, lon1)
    diag::SourceRange range;
};

struct GsScenario {
    std::string name;
    double timeout = 60;
    std::string map;          // the globalconfig's lanelet path, as written
    diag::SourceRange map_range;
    bool collision = true;
    GeoPoint origin;
    double origin_alt = 0;
    bool has_origin = false;
    std::vector<GsVehicle> vehicles;
    std::vector<GsPedestrian> pedestrians;
    std::map<std::string, std::vector<GeoPoint>> routes;
    std::map<std::string, std::vector<GsTnode>> trajectories;
    std::map<std::string, std::vector<GsPathNode>> paths;
    std::map<std::string, GeoPoint> locations;  // gs=location nodes, by name
    std::vector<GsLight> lights;
    std::vector<GsObject> objects;
    std::optional<GeoPoint> egostart;       // the reference's external vehicle 99, 'Ego'
    std::optional<double> ego_orientation;  // degrees, as a vehicle's yaw
};

// Reads and validates a scenario already in `sm`. nullopt after errors (E0910–E0913).
std::optional<GsScenario> read_geoscenario(diag::FileId file, const diag::SourceManager& sm, diag::DiagnosticEngine& diags);

struct ConvertOptions {
    std::vector<std::string> btree_path;  // directories searched for .btree files
    std::vector<std::string> map_dirs;    // directories searched for the map (then the scenario's
                                          // directory and its parents)
    // Relative paths in the output (the map) are written relative to this directory; empty:
    // absolute paths.
    std::string out_dir;
};

struct Converted {
    std::string text;                      // the .sdv source
    std::vector<std::string> btree_files;  // the .btree files it was built from
};

// Converts the scenario at `path` (read into `sm`) and its trees. nullopt after errors.
std::optional<Converted> convert_geoscenario(const std::string& path, const ConvertOptions& options,
                                             diag::SourceManager& sm, diag::DiagnosticEngine& diags);

// Converts .btree files alone (their trees and subtrees, no scenario).
std::optional<Converted> convert_btrees(const std::vector<std::string>& paths, const ConvertOptions& options,
                                        diag::SourceManager& sm, diag::DiagnosticEngine& diags);

// Whether a path names a GeoScenario input: a .btree file or an .osm scenario.
bool is_btree_path(const std::string& path);
bool is_geoscenario_path(const std::string& path);

}  // namespace sdv::compiler::gss
