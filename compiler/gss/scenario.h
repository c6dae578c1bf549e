// The GeoScenario 2.0 front end: reads a scenario (.gs.osm, OSM XML; SPEC §8) into a plain
// description, validates it (every problem is an error naming the element, at its line), and
// converts it, with the .btree trees it uses (gss/lower.h), into .sdv source text. `sdv run`
// compiles that text like any .sdv file; `sdv convert` writes it out.
#pragma once

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
    std::string btype;  // SDV, TV, EV, ...
    std::string btree;  // .btree file name (SDV)
    std::string route;  // route name (SDV)
    std::string trajectory;  // trajectory name (TV)
    double speed = 0;
    double length = 4.5, width = 1.8;
    bool goal_ends_simulation = false;
    GeoPoint at;
    diag::SourceRange range;
};

struct GsTnode {
    GeoPoint at;
    double time = 0;
    std::optional<double> speed;
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
    std::map<std::string, std::vector<GeoPoint>> routes;
    std::map<std::string, std::vector<GsTnode>> trajectories;
    std::vector<GsLight> lights;
    std::vector<GsObject> objects;
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
