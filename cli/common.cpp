// What the subcommands share (see common.h).
#include "cli/common.h"

#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include "compiler/diag/render.h"
#include "compiler/gss/scenario.h"
#include "runtime/ir/ir_io.h"

namespace sdv::cli {

const std::vector<std::string> kWarningNames = {"unused-tree", "unused-parameter", "unused-import",
                                                "no-expectations", "gss-ignored-parameter", "gss-extra-tree", "gss-unknown-type",
                                                "gss-ignored-element", "gss-reconfigured-twice", "gss-unreachable"};

WarningFlags extract_warning_flags(std::vector<std::string>& args) {
    WarningFlags f;
    std::vector<std::string> rest;
    for (const auto& a : args) {
        auto known = [&](const std::string& n) {
            if (std::find(kWarningNames.begin(), kWarningNames.end(), n) == kWarningNames.end()) {
                f.unknown.push_back(n);
            }
        };
        if (a == "-Werror") {
            f.policy.all_errors = true;
        } else if (a == "-w") {
            f.policy.disable_all = true;
        } else if (a.rfind("-Werror=", 0) == 0) {
            f.policy.promoted.insert(a.substr(8));
            known(a.substr(8));
        } else if (a.rfind("-Wno-", 0) == 0) {
            f.policy.disabled.insert(a.substr(5));
            known(a.substr(5));
        } else if (a.rfind("-W", 0) == 0 && a.size() > 2) {
            known(a.substr(2));  // -Wname: warnings are on by default
        } else {
            rest.push_back(a);
        }
    }
    args = std::move(rest);
    return f;
}

// Writes `text` to `path`; on failure says so on stderr and returns false.
bool write_file(const std::string& path, std::string_view text) {
    std::ofstream o(path, std::ios::binary);
    o << text;
    if (!o) std::cerr << "sdv: error: cannot write '" << path << "'\n";
    return static_cast<bool>(o);
}

// `sdv view` / `sdv plot`: a report built from a run directory (or the error building it), to
// `out` ('-': stdout); `announce` prints where it went.
int emit_report(const std::string& text, const std::string& error, const std::string& out, bool announce) {
    if (!error.empty()) {
        std::cerr << "sdv: error: " << error << "\n";
        return kFailure;
    }
    if (out == "-") {
        std::cout << text;
        return kOk;
    }
    if (!write_file(out, text)) return kFailure;
    if (announce) std::cout << "wrote " << out << "\n";
    return kOk;
}

// GeoScenario inputs (.btree, .gs.osm) converted to .sdv text; nullopt after errors.
std::optional<std::string> convert_input(const std::string& file, const Common& c, const std::string& out_dir,
                                         diag::SourceManager& sm, diag::DiagnosticEngine& diags) {
    compiler::gss::ConvertOptions opts{c.btree_path, c.map_dirs, out_dir};
    auto conv = compiler::gss::is_btree_path(file) ? compiler::gss::convert_btrees({file}, opts, sm, diags)
                                                   : compiler::gss::convert_geoscenario(file, opts, sm, diags);
    if (!conv) return std::nullopt;
    return conv->text;
}

// Compiles any input: a .sdv file, or a GeoScenario scenario or .btree file through its
// conversion (so both give the same IR as the converted .sdv).
compiler::Compilation compile_input(const std::string& file, const Common& c, diag::SourceManager& sm,
                                    diag::DiagnosticEngine& diags) {
    compiler::CompileOptions opts{c.import_dirs};
    if (compiler::gss::is_btree_path(file) || compiler::gss::is_geoscenario_path(file)) {
        auto text = convert_input(file, c, "", sm, diags);
        if (!text || diags.has_errors()) return {};
        return compiler::compile_source(file + ".sdv", *text, sm, diags, opts);
    }
    return compiler::compile_file(file, sm, diags, opts);
}

// Prints diagnostics (text to stderr, JSON to stdout) and returns whether there were errors.
bool report(diag::DiagnosticEngine& diags, const diag::SourceManager& sm, const Common& c) {
    if (c.format == "json") {
        std::cout << diag::render_all_json(diags, sm) << "\n";
    } else {
        std::cerr << diag::render_all_text(diags, sm);
    }
    return diags.has_errors();
}

int load_scenario(const std::string& file, const std::string& scenario, const Common& c, const WarningFlags& w,
                  Loaded& out, bool all_if_several) {
    {
        // What the compiler says of a file it cannot read, as it says it (E0006 and the count).
        std::error_code ec;
        std::ifstream in(file, std::ios::binary);
        if (std::filesystem::is_directory(file, ec) || !in) {
            diag::SourceManager sm;
            diag::DiagnosticEngine diags;
            compiler::compile_file(file, sm, diags);
            report(diags, sm, c);
            return kFailure;
        }
        std::stringstream ss;
        ss << in.rdbuf();
        out.text = ss.str();
    }
    const bool is_ir = file.size() > 6 && file.compare(file.size() - 6, 6, ".sdvir") == 0;
    std::optional<ir::Program> program;
    if (compiler::gss::is_geoscenario_path(file)) {
        diag::SourceManager sm;
        diag::DiagnosticEngine diags;
        diags.set_policy(w.policy);
        auto result = compile_input(file, c, sm, diags);
        if (report(diags, sm, c) || !result.program) return kFailure;
        program = std::move(result.program);
    } else if (is_ir) {
        auto r = ir::read_ir(out.text);
        if (!r.program) {
            std::cerr << file << ": error: " << r.error << "\n";
            return kFailure;
        }
        program = std::move(r.program);
    } else {
        diag::SourceManager sm;
        diag::DiagnosticEngine diags;
        diags.set_policy(w.policy);
        compiler::CompileOptions opts{c.import_dirs};
        auto result = compiler::compile_source(file, out.text, sm, diags, opts);
        if (report(diags, sm, c) || !result.program) return kFailure;
        program = std::move(result.program);
    }
    if (program->scenarios.empty()) {
        std::cerr << "sdv: error: '" << file << "' has no scenario to run\n";
        return kFailure;
    }
    int index = 0;
    if (!scenario.empty()) {
        index = -1;
        for (size_t i = 0; i < program->scenarios.size(); ++i) {
            if (program->scenarios[i].name == scenario) index = static_cast<int>(i);
        }
        if (index < 0) {
            std::cerr << "sdv: error: no scenario '" << scenario << "' in '" << file << "'\n";
            return kFailure;
        }
    } else if (program->scenarios.size() > 1 && all_if_several) {
        index = -1;
    } else if (program->scenarios.size() > 1) {
        std::cerr << "sdv: error: '" << file << "' has several scenarios; choose one with --scenario\n";
        return kUsage;
    }
    out.program = std::move(*program);
    out.index = index;
    return kOk;
}

}  // namespace sdv::cli
