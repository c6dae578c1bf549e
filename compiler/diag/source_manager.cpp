// Line tables are built once per file; lookups are a binary search, so 10 MB files are fine.
#include "compiler/diag/source_manager.h"

#include <algorithm>

namespace sdv::diag {

FileId SourceManager::add_file(std::string path, std::string contents) {
    File f;
    f.path = std::move(path);
    f.contents = std::move(contents);
    f.line_starts.push_back(0);
    uint32_t cps = 0;
    for (size_t i = 0; i < f.contents.size(); ++i) {
        if (i % kCheckpoint == 0) f.code_points.push_back(cps);
        if (f.contents[i] == '\n') f.line_starts.push_back(static_cast<uint32_t>(i + 1));
        // Continuation bytes (10xxxxxx) do not start a code point.
        if ((static_cast<unsigned char>(f.contents[i]) & 0xC0) != 0x80) ++cps;
    }
    f.code_points.push_back(cps);  // at the end (a checkpoint past the last full block)
    files_.push_back(std::move(f));
    return static_cast<FileId>(files_.size());
}

const SourceManager::File* SourceManager::get(FileId file) const {
    if (file == 0 || file > files_.size()) return nullptr;
    return &files_[file - 1];
}

const std::string& SourceManager::path(FileId file) const {
    static const std::string kNone;
    const File* f = get(file);
    return f != nullptr ? f->path : kNone;
}

std::string_view SourceManager::contents(FileId file) const {
    const File* f = get(file);
    return f != nullptr ? std::string_view(f->contents) : std::string_view();
}

SourceManager::LineCol SourceManager::line_col(SourceLocation loc) const {
    const File* f = get(loc.file);
    if (f == nullptr) return {};
    const uint32_t offset = std::min<uint32_t>(loc.offset, static_cast<uint32_t>(f->contents.size()));
    auto it = std::upper_bound(f->line_starts.begin(), f->line_starts.end(), offset);
    const auto line = static_cast<uint32_t>(it - f->line_starts.begin());
    const uint32_t start = f->line_starts[line - 1];
    return {line, 1 + code_points_before(*f, offset) - code_points_before(*f, start)};
}

uint32_t SourceManager::code_points_before(const File& f, uint32_t offset) {
    const uint32_t block = offset / kCheckpoint;
    if (block >= f.code_points.size()) return f.code_points.back();
    uint32_t n = f.code_points[block];
    for (uint32_t i = block * kCheckpoint; i < offset; ++i) {
        if ((static_cast<unsigned char>(f.contents[i]) & 0xC0) != 0x80) ++n;
    }
    return n;
}

std::string_view SourceManager::line_text(FileId file, uint32_t line) const {
    const File* f = get(file);
    if (f == nullptr || line == 0 || line > f->line_starts.size()) return {};
    const uint32_t start = f->line_starts[line - 1];
    uint32_t end = line < f->line_starts.size() ? f->line_starts[line] - 1
                                                : static_cast<uint32_t>(f->contents.size());
    if (end > start && f->contents[end - 1] == '\r') --end;
    return std::string_view(f->contents).substr(start, end - start);
}

}  // namespace sdv::diag
