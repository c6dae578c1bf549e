// A diagnostic: severity, stable code, location, message and notes.
#pragma once

#include <string>
#include <vector>

#include "compiler/diag/source_manager.h"

namespace sdv::diag {

enum class Severity { note, warning, error };

struct Note {
    SourceRange range;  // may be invalid: a note without location
    std::string message;
};

struct Diagnostic {
    Severity severity = Severity::error;
    std::string code;          // "E0203"; warnings "W0101"
    std::string warning_name;  // "unused-tree"; empty for errors
    SourceRange range;
    std::string message;
    std::vector<Note> notes;
};

}  // namespace sdv::diag
