// Collects the diagnostics of a compilation, applies the warning policy (-Wno-NAME,
// -Werror=NAME, -Werror) and caps their number, then hands them out sorted by position.
#pragma once

#include <set>
#include <string>
#include <vector>

#include "compiler/diag/diagnostic.h"

namespace sdv::diag {

class DiagnosticEngine {
public:
    struct WarningPolicy {
        bool all_errors = false;            // -Werror
        std::set<std::string> disabled;     // -Wno-NAME
        std::set<std::string> promoted;     // -Werror=NAME
        bool disable_all = false;           // -w
    };

    // Adds an error and returns it so the caller can attach notes. Past the error limit the
    // returned diagnostic is a scratch one that is never reported.
    Diagnostic& error(std::string code, SourceRange range, std::string message);
    Diagnostic& warning(std::string code, std::string name, SourceRange range,
                        std::string message);
    void report(Diagnostic d);
    // The last diagnostic reported with this code at this place, to add a note to later.
    Diagnostic* find(const std::string& code, SourceRange range);

    void set_policy(WarningPolicy policy) { policy_ = std::move(policy); }
    void set_error_limit(size_t n) { limit_ = n; }
    bool limit_reached() const { return errors_ >= limit_; }

    // Counts after the policy: promoted warnings count as errors, disabled ones not at all.
    bool has_errors() const { return error_count() > 0; }
    size_t error_count() const;
    size_t warning_count() const;

    // The reported diagnostics with the policy applied, stable-sorted by (file, offset).
    std::vector<Diagnostic> sorted() const;

private:
    enum class Effect { drop, warn, error };
    Effect effect(const Diagnostic& d) const;

    WarningPolicy policy_;
    std::vector<Diagnostic> items_;
    size_t errors_ = 0;
    size_t limit_ = 100;
    bool limit_noted_ = false;
    Diagnostic scratch_;
};

}  // namespace sdv::diag
