// The report of a test campaign (`sdv sweep --report`, `sdv view SWEEP_DIR`): one
// self-contained HTML page (runtime/io/viewer/sweep_report.html, data inlined as JSON, format
// "sdv-sweep-report/1") summarising a sweep directory: its header counts, the outcome of every
// variant over the varied parameters (heat map, scatter, outcome-vs-parameter plot or parallel
// coordinates), a colour legend and a sortable table, with links to the kept runs' own reports.
//
// A sweep directory holds results.csv and summary.json ("sdv-sweep/1") and, for kept variants,
// runs/<variant>/view.html. The links are relative, so the page is meant to be written into the
// sweep directory itself (DIR/report.html).
#pragma once

#include <string>
#include <string_view>

namespace sdv::io {

// The sweep report page with its data placeholder (embedded at build time).
std::string_view sweep_report_template();

// The HTML report of the sweep directory `dir` (DIR/results.csv + DIR/summary.json):
// self-contained (no network), data embedded as JSON. Returns "" and sets `error` (one line
// naming the file and the line/column) when the directory is not a readable sweep. Never throws.
std::string sweep_report(const std::string& dir, std::string& error);

}  // namespace sdv::io
