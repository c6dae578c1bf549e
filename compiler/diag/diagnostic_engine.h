// Collects the diagnostics of a compilation, applies the warning policy (-Wno-NAME,
// -Werror=NAME, -Werror) as each is reported and caps their number (100 errors, 100 warnings:
// a file of thousands of diagnostics stays fast and readable), then hands them out sorted by
// position. Set the policy before reporting.
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
    // returned diagnostic is a scratch one that is never reported (E0007 says so once).
    Diagnostic& error(std::string code, SourceRange range, std::string message);
    // Adds a warning, or an error if the policy promotes it. A warning the policy disables, or
    // one past the warning limit, is a scratch one that is never reported; those past the limit
    // are counted, and one note (W0001) gives their number.
    Diagnostic& warning(std::string code, std::string name, SourceRange range,
                        std::string message);
    void report(Diagnostic d);
    // The last diagnostic reported with this code at this place, to add a note to later.
    Diagnostic* find(const std::string& code, SourceRange range);

    void set_policy(WarningPolicy policy) { policy_ = std::move(policy); }
    void set_error_limit(size_t n) { limit_ = n; }
    void set_warning_limit(size_t n) { warning_limit_ = n; }
    bool limit_reached() const { return errors_ >= limit_; }

    // Counts after the policy: promoted warnings count as errors (and E0007 as one), disabled
    // ones not at all; warnings past the limit count. Constant time.
    bool has_errors() const { return error_count() > 0; }
    size_t error_count() const { return errors_ + (limit_noted_ ? 1 : 0); }
    size_t warning_count() const { return warnings_ + unshown_warnings_; }

    // The reported diagnostics with the policy applied (promoted warnings are errors),
    // stable-sorted by (file, offset); the notes of the limits last.
    std::vector<Diagnostic> sorted() const;

private:
    enum class Effect { drop, warn, error };
    Effect effect(const Diagnostic& d) const;
    Diagnostic& add(Diagnostic d);

    WarningPolicy policy_;
    std::vector<Diagnostic> items_;
    size_t errors_ = 0;
    size_t warnings_ = 0;
    size_t unshown_warnings_ = 0;
    size_t limit_ = 100;
    size_t warning_limit_ = 100;
    bool limit_noted_ = false;
    Diagnostic scratch_;
};

}  // namespace sdv::diag
