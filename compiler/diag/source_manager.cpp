// Line tables are built once per file; lookups are a binary search, so 10 MB files are fine.
#include "compiler/diag/source_manager.h"

#include <algorithm>

namespace sdv::diag {

FileId SourceManager::add_file(std::string path, std::string contents) {
    File f;
    f.path = std::move(path);
    f.contents = std::move(contents);
    f.line_starts.push_back(0);
    for (size_t i = 0; i < f.contents.size(); ++i) {
        if (f.contents[i] == '\n') f.line_starts.push_back(static_cast<uint32_t>(i + 1));
    }
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
    uint32_t col = 1;
    for (uint32_t i = start; i < offset; ++i) {
        // Count code points: continuation bytes (10xxxxxx) do not start a column.
        if ((static_cast<unsigned char>(f->contents[i]) & 0xC0) != 0x80) ++col;
    }
    return {line, col};
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
