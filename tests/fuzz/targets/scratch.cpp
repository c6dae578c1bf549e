// The scratch directory and the failure report of the fuzz targets (scratch.h).
#include "tests/fuzz/targets/scratch.h"

#include <signal.h>
#include <stdlib.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <filesystem>
#include <fstream>

namespace fs = std::filesystem;

namespace sdv::fuzz {
namespace {

constexpr const char* kPrefix = "sdv-fuzz-";

// Removes the scratch directories of processes that no longer exist (named with their pid).
void remove_orphans(const fs::path& parent) {
    std::error_code ec;
    for (fs::directory_iterator it(parent, ec), end; !ec && it != end; it.increment(ec)) {
        const std::string name = it->path().filename().string();
        if (name.rfind(kPrefix, 0) != 0) continue;
        const std::string rest = name.substr(std::string(kPrefix).size());
        const size_t dash = rest.find('-');
        if (dash == std::string::npos || dash == 0) continue;
        char* end_ptr = nullptr;
        const long pid = std::strtol(rest.c_str(), &end_ptr, 10);
        if (end_ptr != rest.c_str() + dash || pid <= 0) continue;
        if (kill(static_cast<pid_t>(pid), 0) == 0 || errno != ESRCH) continue;
        std::error_code ignored;
        fs::remove_all(it->path(), ignored);
    }
}

struct Scratch {
    fs::path root;
    Scratch() {
        std::error_code ec;
        fs::path parent = "/dev/shm";
        if (!fs::is_directory(parent, ec) || access(parent.c_str(), W_OK) != 0) parent = fs::temp_directory_path(ec);
        remove_orphans(parent);
        std::string templ = (parent / (kPrefix + std::to_string(getpid()) + "-XXXXXX")).string();
        if (mkdtemp(templ.data()) == nullptr) {
            std::perror("sdv fuzz: cannot create a scratch directory");
            std::abort();
        }
        root = templ;
    }
    ~Scratch() {
        std::error_code ec;
        fs::remove_all(root, ec);
    }
};

Scratch& scratch() {
    static Scratch s;
    return s;
}

}  // namespace

std::string fresh_dir(const std::string& name) {
    const fs::path dir = scratch().root / name;
    std::error_code ec;
    fs::remove_all(dir, ec);
    fs::create_directories(dir, ec);
    if (ec) {
        std::fprintf(stderr, "sdv fuzz: cannot create %s: %s\n", dir.c_str(), ec.message().c_str());
        std::abort();
    }
    return dir.string();
}

void write_file(const std::string& path, std::string_view bytes) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    if (!out) {
        std::fprintf(stderr, "sdv fuzz: cannot write %s\n", path.c_str());
        std::abort();
    }
}

const std::vector<std::string>& btree_library() {
    static const std::vector<std::string> dirs = [] {
        std::vector<std::string> out;
        for (const char* sub : {"sdv", "sp"}) {
            const fs::path d = fs::path(SDV_SHARED_DIR) / "data" / "geoscenario" / "btrees" / sub;
            std::error_code ec;
            if (fs::is_directory(d, ec)) out.push_back(d.lexically_normal().string());
        }
        return out;
    }();
    return dirs;
}

void fail(const char* target, const std::string& what) {
    std::fprintf(stderr, "sdv fuzz: %s: property broken: %s\n", target, what.c_str());
    std::fflush(stderr);
    std::abort();
}

compiler::CompileOptions compile_options() {
    compiler::CompileOptions options;
    options.max_scenario_agents = 2000;
    options.max_scenario_tree_nodes = 3000;
    options.max_scenario_tree_path_chars = 300000;
    return options;
}

void require_converted_text_compiles(const char* target, const std::string& display, const diag::SourceManager& sm,
                                     const diag::DiagnosticEngine& diags) {
    for (const auto& d : diags.sorted()) {
        if (d.severity != diag::Severity::error || d.range.begin.file == 0 || sm.path(d.range.begin.file) != display) continue;
        if (d.code == "E0306" || d.code == "E0511") continue;
        fail(target, "the converter accepted the input, but its .sdv text does not compile: " + d.code + " " + d.message + ": " +
                         std::string(sm.line_text(d.range.begin.file, sm.line_col(d.range.begin).line)));
    }
}

namespace {

// Whether `r` lies within a file of `sm`.
bool within(const diag::SourceManager& sm, const diag::SourceRange& r) {
    if (r.begin.file == 0 || r.begin.file > sm.file_count() || r.end.file != r.begin.file) return false;
    const size_t size = sm.contents(r.begin.file).size();
    return r.begin.offset <= r.end.offset && r.end.offset <= size;
}

}  // namespace

void require_located_diagnostics(const char* target, const diag::SourceManager& sm, const diag::DiagnosticEngine& diags) {
    for (const auto& d : diags.sorted()) {
        const std::string what = "diagnostic " + d.code + " (" + d.message + ")";
        const bool code = d.code.size() == 5 && (d.code[0] == 'E' || d.code[0] == 'W') &&
                          std::all_of(d.code.begin() + 1, d.code.end(), [](char c) { return c >= '0' && c <= '9'; });
        if (!code) fail(target, what + " has no code of the form E0000 or W0000");
        if (d.message.empty()) fail(target, what + " has no message");
        const bool placeless = d.code == "E0007" || d.code == "W0001";
        if (!placeless && !within(sm, d.range)) {
            const auto& r = d.range;
            fail(target, what + " has no place within its file (file " + std::to_string(r.begin.file) + " bytes " +
                             std::to_string(r.begin.offset) + ".." + std::to_string(r.end.offset) + " of file " +
                             std::to_string(r.end.file) + "; " + std::to_string(sm.file_count()) + " files)");
        }
        for (const auto& n : d.notes)
            if (n.range.valid() && !within(sm, n.range)) fail(target, what + " has a note whose place is outside its file");
    }
}

}  // namespace sdv::fuzz
