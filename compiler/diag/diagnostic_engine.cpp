// The limits keep pathological inputs (a 10 MB file of errors, a line of 4,000 ignored
// arguments) fast and readable: the engine never holds more than about 200 diagnostics, so
// rendering and the checker's lookups cost the same however many the input would produce.
#include "compiler/diag/diagnostic_engine.h"

#include <algorithm>

namespace sdv::diag {

Diagnostic& DiagnosticEngine::error(std::string code, SourceRange range, std::string message) {
    Diagnostic d;
    d.severity = Severity::error;
    d.code = std::move(code);
    d.range = range;
    d.message = std::move(message);
    return add(std::move(d));
}

Diagnostic& DiagnosticEngine::warning(std::string code, std::string name, SourceRange range,
                                      std::string message) {
    Diagnostic d;
    d.severity = Severity::warning;
    d.code = std::move(code);
    d.warning_name = std::move(name);
    d.range = range;
    d.message = std::move(message);
    return add(std::move(d));
}

void DiagnosticEngine::report(Diagnostic d) { add(std::move(d)); }

Diagnostic& DiagnosticEngine::add(Diagnostic d) {
    switch (effect(d)) {
        case Effect::drop:
            break;
        case Effect::warn:
            if (warnings_ < warning_limit_) {
                ++warnings_;
                items_.push_back(std::move(d));
                return items_.back();
            }
            ++unshown_warnings_;
            break;
        case Effect::error:
            if (errors_ < limit_) {
                ++errors_;
                d.severity = Severity::error;  // a promoted warning keeps its name: -Werror,-WNAME
                items_.push_back(std::move(d));
                return items_.back();
            }
            if (!limit_noted_) {
                limit_noted_ = true;
                Diagnostic note;
                note.code = "E0007";
                note.message = "too many errors (" + std::to_string(limit_) + "); stopping";
                items_.push_back(std::move(note));
            }
            break;
    }
    scratch_ = Diagnostic{};
    return scratch_;
}

Diagnostic* DiagnosticEngine::find(const std::string& code, SourceRange range) {
    for (auto it = items_.rbegin(); it != items_.rend(); ++it) {
        if (it->code == code && it->range.begin.file == range.begin.file &&
            it->range.begin.offset == range.begin.offset) {
            return &*it;
        }
    }
    return nullptr;
}

DiagnosticEngine::Effect DiagnosticEngine::effect(const Diagnostic& d) const {
    if (d.severity != Severity::warning) return Effect::error;
    if (policy_.promoted.count(d.warning_name)) return Effect::error;
    if (policy_.disable_all || policy_.disabled.count(d.warning_name)) return Effect::drop;
    return policy_.all_errors ? Effect::error : Effect::warn;
}

std::vector<Diagnostic> DiagnosticEngine::sorted() const {
    std::vector<Diagnostic> out = items_;
    // Diagnostics without a file (command line, limits) go last.
    std::stable_sort(out.begin(), out.end(), [](const Diagnostic& a, const Diagnostic& b) {
        const auto ka = a.range.begin.file == 0 ? UINT32_MAX : a.range.begin.file;
        const auto kb = b.range.begin.file == 0 ? UINT32_MAX : b.range.begin.file;
        if (ka != kb) return ka < kb;
        return a.range.begin.offset < b.range.begin.offset;
    });
    if (unshown_warnings_ > 0) {
        Diagnostic d;
        d.severity = Severity::note;
        d.code = "W0001";
        d.message = std::to_string(unshown_warnings_) + " more warning" +
                    (unshown_warnings_ == 1 ? "" : "s") + " not shown (the first " +
                    std::to_string(warning_limit_) + " are); -Wno-NAME silences a kind";
        out.push_back(std::move(d));
    }
    return out;
}

}  // namespace sdv::diag
