// Fuzz target of the run directory reader: what `sdv view RUN_DIR` (runtime/io/view.h
// view_report) and `sdv plot RUN_DIR` (runtime/io/plot.h plot_run) read, the outputs of
// `sdv run -o` that users pass around. The input is the directory's files, separated by NUL
// bytes, in this order: trajectories.csv, summary.json, road.json, decisions.jsonl,
// recorded.csv; the files after the last part are absent (no NUL: trajectories.csv alone).
//
// Properties: a run that is refused says why; the report's data (the JSON the page reads with
// JSON.parse) parses and cannot end its <script> element; the plot is well-formed XML of the
// elements a plot draws.
#include <pugixml.hpp>

#include <nlohmann/json.hpp>

#include <set>
#include <string>
#include <string_view>

#include "runtime/io/plot.h"
#include "runtime/io/view.h"
#include "tests/fuzz/targets/scratch.h"
#include "tests/fuzz/targets/targets.h"

using namespace sdv;

namespace {

constexpr const char* kTarget = "run_dir";
constexpr const char* kFiles[] = {"trajectories.csv", "summary.json", "road.json", "decisions.jsonl", "recorded.csv"};

void check_view(const std::string& html) {
    const std::string_view page = io::viewer_template();
    const std::string_view marker = "__SDV_DATA__";
    const size_t at = page.find(marker);
    const std::string_view before = page.substr(0, at), after = page.substr(at + marker.size());
    if (html.size() < before.size() + after.size() || html.compare(0, before.size(), before) != 0 ||
        html.compare(html.size() - after.size(), after.size(), after) != 0) {
        fuzz::fail(kTarget, "the report is not the viewer page with its data in the placeholder");
    }
    const std::string_view data(html.data() + before.size(), html.size() - before.size() - after.size());
    // '<' only as its JSON escape: "</script>" or "<!--" in the data would end the element early.
    if (data.find('<') != std::string_view::npos) fuzz::fail(kTarget, "the report's data contains '<'");
    // Validated without building it (at the tick limit the data is half a megabyte of JSON).
    if (!nlohmann::json::accept(data)) fuzz::fail(kTarget, "the report's data is not JSON");
    if (data.rfind(R"({"format":"sdv-view/1",)", 0) != 0) fuzz::fail(kTarget, "the report's data is not an object of format sdv-view/1");
}

void check_plot(const std::string& svg) {
    pugi::xml_document doc;
    const auto ok = doc.load_buffer(svg.data(), svg.size());
    if (!ok) fuzz::fail(kTarget, std::string("the plot is not well-formed XML: ") + ok.description());
    if (std::string_view(doc.document_element().name()) != "svg") fuzz::fail(kTarget, "the plot is not an <svg>");
    // Only the elements a plot draws: a name read from the run cannot add one (a <script>).
    struct Walker : pugi::xml_tree_walker {
        bool for_each(pugi::xml_node& node) override {
            if (node.type() != pugi::node_element) return true;
            static const std::set<std::string_view> kDrawn = {"svg", "rect", "g", "polyline", "circle", "text", "tspan", "defs", "pattern"};
            if (!kDrawn.count(node.name())) fuzz::fail(kTarget, std::string("the plot has an element <") + node.name() + ">");
            return true;
        }
    } walker;
    doc.traverse(walker);
}

}  // namespace

int sdv_fuzz_run_dir(const uint8_t* data, size_t size) {
    std::string_view bytes(reinterpret_cast<const char*>(data), size);
    const std::string dir = fuzz::fresh_dir(kTarget);
    for (const char* name : kFiles) {
        const size_t nul = bytes.find('\0');
        fuzz::write_file(dir + "/" + name, bytes.substr(0, nul));
        if (nul == std::string_view::npos) break;
        bytes.remove_prefix(nul + 1);
    }
    std::string error;
    const std::string html = io::view_report(dir, error);
    if (html.empty() == error.empty()) fuzz::fail(kTarget, "view: " + std::string(html.empty() ? "no report and no error" : "a report and an error"));
    if (!html.empty()) check_view(html);
    error.clear();
    const std::string svg = io::plot_run(dir, error);
    if (svg.empty() == error.empty()) fuzz::fail(kTarget, "plot: " + std::string(svg.empty() ? "no plot and no error" : "a plot and an error"));
    if (!svg.empty()) check_plot(svg);
    return 0;
}
