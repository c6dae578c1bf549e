// Owns the text of every file a compilation reads and maps byte offsets to line and column.
// FileId 0 means "no file" (diagnostics about the command line); real files start at 1.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace sdv::diag {

using FileId = uint32_t;

struct SourceLocation {
    FileId file = 0;
    uint32_t offset = 0;  // bytes from the start of the file
};

struct SourceRange {
    SourceLocation begin, end;  // end is exclusive

    bool valid() const { return begin.file != 0; }
};

class SourceManager {
public:
    struct LineCol {
        uint32_t line = 0;  // 1-based
        uint32_t col = 0;   // 1-based, in code points (a tab counts as one)
    };

    FileId add_file(std::string path, std::string contents);
    const std::string& path(FileId file) const;
    std::string_view contents(FileId file) const;
    LineCol line_col(SourceLocation loc) const;
    // The text of a 1-based line, without its line break.
    std::string_view line_text(FileId file, uint32_t line) const;
    size_t file_count() const { return files_.size(); }

private:
    struct File {
        std::string path;
        std::string contents;
        std::vector<uint32_t> line_starts;  // byte offset of each line's first byte
        // Code points before byte k * kCheckpoint: a column is found by scanning at most
        // kCheckpoint bytes, however long its line (a 10 MB file may be one line).
        std::vector<uint32_t> code_points;
    };
    static constexpr uint32_t kCheckpoint = 256;
    // Code points before byte `offset` of `f`.
    static uint32_t code_points_before(const File& f, uint32_t offset);
    const File* get(FileId file) const;

    std::vector<File> files_;
};

}  // namespace sdv::diag
