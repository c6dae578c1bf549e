// Fuzz target of the readers of recorded traffic (docs/realism.md): a CommonRoad file (its
// lanelet network by road::parse_commonroad, its dynamic obstacles and light cycles by
// realism::parse_commonroad) or an INTERACTION track file (on a fixed built-in road), then what
// `sdv replay` does with the first recorded vehicle: its route over the network, the replay
// scenario's text, and that text compiled. Properties: a reader gives a result or errors, never
// both missing; every read track has states in increasing time with finite values; the text
// generated for a track that has a route compiles without errors, and nothing of the recording adds
// statements to it (one scenario, one map, the recording's lights, one expectation, std/ imports only).
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <string>

#include "compiler/recorded/replay.h"
#include "compiler/sema/compile.h"
#include "runtime/realism/recording.h"
#include "runtime/realism/route.h"
#include "runtime/road/builtin_road.h"
#include "runtime/road/commonroad_reader.h"
#include "tests/fuzz/targets/scratch.h"
#include "tests/fuzz/targets/targets.h"

using namespace sdv;

namespace {

constexpr const char* kTarget = "recording";

// The replay's map declaration names a file that the checker requires to exist: the input itself,
// written to a file of this process (the checker does not read it).
const std::string& map_file(const std::string& text) {
    static const std::string path = "/tmp/sdv-fuzz-recording-" + std::to_string(::getpid()) + ".xml";
    if (FILE* f = std::fopen(path.c_str(), "wb")) {
        std::fwrite(text.data(), 1, text.size(), f);
        std::fclose(f);
    }
    return path;
}

void check_tracks(const realism::Recording& rec) {
    if (rec.errors.empty() && rec.tracks.empty()) fuzz::fail(kTarget, "no track and no error");
    for (const auto& t : rec.tracks) {
        if (t.states.empty()) fuzz::fail(kTarget, "a track without states: " + t.id);
        for (size_t i = 0; i < t.states.size(); ++i) {
            const auto& s = t.states[i];
            if (!std::isfinite(s.t) || !std::isfinite(s.x) || !std::isfinite(s.y) || !std::isfinite(s.heading) ||
                !std::isfinite(s.speed))
                fuzz::fail(kTarget, "a state with a value that is not finite in track " + t.id);
            if (i > 0 && !(s.t > t.states[i - 1].t)) fuzz::fail(kTarget, "states out of time order in track " + t.id);
        }
    }
}

// The replay of the first vehicle with at least two states: its text must compile.
void replay_first(realism::Recording& rec, const road::RoadNetwork& net) {
    if (!rec.errors.empty()) return;
    for (const auto& t : rec.tracks) {
        if (t.pedestrian() || t.states.size() < 2) continue;
        if (!realism::recorded_route(net, t, 30).error.empty()) return;
        compiler::recorded::ReplaySpec spec;
        spec.sdv = t.id;
        const auto src = compiler::recorded::replay_source(rec, net, spec);
        if (!src.error.empty()) return;
        diag::SourceManager sm;
        diag::DiagnosticEngine diags;
        auto c = compiler::compile_source("replay.sdv", src.text, sm, diags);
        if (!c.program) {
            std::string first;
            for (const auto& d : diags.sorted())
                if (d.severity == diag::Severity::error && first.empty()) first = d.code + " " + d.message;
            fuzz::fail(kTarget, "the replay of track " + t.id + " does not compile: " + first);
        }
        // Nothing of the recording adds statements: the text declares the one scenario, with the
        // recording's lights and one expectation, over the one map, importing only std/.
        const ir::Program& p = *c.program;
        for (size_t f = 1; f < p.files.size(); ++f) {
            if (p.files[f].rfind("std/", 0) != 0) fuzz::fail(kTarget, "the replay imports " + p.files[f]);
        }
        for (const auto& tree : p.trees) {
            if (tree.name.rfind("std.", 0) != 0) fuzz::fail(kTarget, "the replay declares a tree " + tree.name);
        }
        if (p.scenarios.size() != 1 || p.roads.size() != 1 || p.scenarios[0].expect_roots.size() != 1 ||
            p.scenarios[0].lights.size() != rec.lights.size()) {
            fuzz::fail(kTarget, "the replay of track " + t.id + " has " + std::to_string(p.scenarios.size()) +
                                    " scenarios, " + std::to_string(p.roads.size()) + " roads, or other expectations or lights");
        }
        return;
    }
}

}  // namespace

int sdv_fuzz_recording(const uint8_t* data, size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    if (road::is_commonroad(text)) {
        auto net = road::parse_commonroad(text);
        if (!net.network && net.errors.empty()) fuzz::fail(kTarget, "no network and no error");
        if (net.network && !net.errors.empty()) fuzz::fail(kTarget, "a network although there were errors");
        auto rec = realism::parse_commonroad(text, "fuzz.xml");
        check_tracks(rec);
        if (net.network) {
            net.network->prepare();
            rec.map_path = map_file(text);
            replay_first(rec, *net.network);
        }
        return 0;
    }
    auto rec = realism::parse_interaction(text, "fuzz.csv");
    check_tracks(rec);
    static const road::RoadNetwork road = [] {
        road::RoadSpec spec;
        auto b = road::build_road(spec);
        b.network.prepare();
        return std::move(b.network);
    }();
    rec.map_path = map_file(text);
    replay_first(rec, road);
    return 0;
}
