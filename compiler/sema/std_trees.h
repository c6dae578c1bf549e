// The standard tree library as its users see it: every `tree` of the embedded std/*.sdv files
// with its parameters (name, type, default as written) and its doc comment (the `#` lines right
// above it). `sdv catalog --trees` prints it and docs/catalog.md is generated from it, so the
// parameters of std.drive or std.brake_when_close are documented where the trees are written.
#pragma once

#include <string>
#include <vector>

namespace sdv::compiler {

struct StdTree {
    struct Param {
        std::string name, type, def;  // def: as written ("14 m/s"), empty when required
    };
    std::string name;  // "std.drive"
    std::string file;  // "std/drive.sdv"
    std::string doc;   // its comment, lines joined with '\n', without the '#'
    std::vector<Param> params;
};

// In file and declaration order.
std::vector<StdTree> std_trees();

std::string render_std_trees_text(const std::vector<StdTree>& trees);
std::string render_std_trees_markdown(const std::vector<StdTree>& trees);
std::string render_std_trees_json(const std::vector<StdTree>& trees);

}  // namespace sdv::compiler
