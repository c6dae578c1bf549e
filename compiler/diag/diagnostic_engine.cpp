// The error limit keeps pathological inputs (a 10 MB file of errors) fast and readable.
#include "compiler/diag/diagnostic_engine.h"

#include <algorithm>

namespace sdv::diag {

Diagnostic& DiagnosticEngine::error(std::string code, SourceRange range, std::string message) {
    if (errors_ >= limit_) {
        if (!limit_noted_) {
            limit_noted_ = true;
            Diagnostic d;
            d.code = "E0007";
            d.message = "too many errors (" + std::to_string(limit_) + "); stopping";
            items_.push_back(std::move(d));
        }
        scratch_ = Diagnostic{};
        return scratch_;
    }
    ++errors_;
    Diagnostic d;
    d.severity = Severity::error;
    d.code = std::move(code);
    d.range = range;
    d.message = std::move(message);
    items_.push_back(std::move(d));
    return items_.back();
}

Diagnostic& DiagnosticEngine::warning(std::string code, std::string name, SourceRange range,
                                      std::string message) {
    Diagnostic d;
    d.severity = Severity::warning;
    d.code = std::move(code);
    d.warning_name = std::move(name);
    d.range = range;
    d.message = std::move(message);
    items_.push_back(std::move(d));
    return items_.back();
}

void DiagnosticEngine::report(Diagnostic d) {
    if (d.severity == Severity::error) {
        Diagnostic& slot = error(d.code, d.range, d.message);
        slot.notes = std::move(d.notes);
        return;
    }
    items_.push_back(std::move(d));
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

size_t DiagnosticEngine::error_count() const {
    size_t n = 0;
    for (const auto& d : items_) n += effect(d) == Effect::error;
    return n;
}

size_t DiagnosticEngine::warning_count() const {
    size_t n = 0;
    for (const auto& d : items_) n += effect(d) == Effect::warn;
    return n;
}

std::vector<Diagnostic> DiagnosticEngine::sorted() const {
    std::vector<Diagnostic> out;
    for (const auto& d : items_) {
        const Effect e = effect(d);
        if (e == Effect::drop) continue;
        Diagnostic copy = d;
        if (e == Effect::error) copy.severity = Severity::error;
        out.push_back(std::move(copy));
    }
    // Diagnostics without a file (command line, limits) go last.
    std::stable_sort(out.begin(), out.end(), [](const Diagnostic& a, const Diagnostic& b) {
        const auto ka = a.range.begin.file == 0 ? UINT32_MAX : a.range.begin.file;
        const auto kb = b.range.begin.file == 0 ? UINT32_MAX : b.range.begin.file;
        if (ka != kb) return ka < kb;
        return a.range.begin.offset < b.range.begin.offset;
    });
    return out;
}

}  // namespace sdv::diag
