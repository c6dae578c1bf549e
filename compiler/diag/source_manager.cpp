// Line tables are built once per file; lookups are a binary search, so 10 MB files are fine.
#include "compiler/diag/source_manager.h"

#include <algorithm>
#include <bit>
#include <cstring>

namespace sdv::diag {

namespace {

// The code points that start in text[0, n): every byte but the continuation bytes (10xxxxxx).
// Eight bytes a step, without a comparison per byte (under the fuzzers' coverage, tests/fuzz,
// each comparison of a byte loop is a call into libFuzzer).
uint32_t count_code_points(const char* text, size_t n) {
    constexpr uint64_t kHigh = 0x8080808080808080ULL;
    size_t continuation = 0, i = 0;
    for (; i + 8 <= n; i += 8) {
        uint64_t w;
        std::memcpy(&w, text + i, 8);
        // Bit 7 of each byte set, and bit 6 (shifted to bit 7 of the same byte) clear.
        continuation += static_cast<size_t>(std::popcount(w & ~(w << 1) & kHigh));
    }
    for (; i < n; ++i) continuation += (static_cast<unsigned char>(text[i]) & 0xC0) == 0x80 ? 1 : 0;
    return static_cast<uint32_t>(n - continuation);
}

}  // namespace

FileId SourceManager::add_file(std::string path, std::string contents) {
    File f;
    f.path = std::move(path);
    f.contents = std::move(contents);
    const char* const text = f.contents.data();
    const size_t size = f.contents.size();
    f.line_starts.push_back(0);
    // The line breaks by memchr: the C library's scan, vectorised and not instrumented.
    for (const char* p = text; (p = static_cast<const char*>(std::memchr(p, '\n', size - (p - text)))) != nullptr;) {
        ++p;
        f.line_starts.push_back(static_cast<uint32_t>(p - text));
    }
    f.code_points.reserve(size / kCheckpoint + 2);
    uint32_t cps = 0;
    for (size_t block = 0; block < size; block += kCheckpoint) {
        f.code_points.push_back(cps);
        cps += count_code_points(text + block, std::min<size_t>(kCheckpoint, size - block));
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
    const uint32_t start = block * kCheckpoint;
    return f.code_points[block] + count_code_points(f.contents.data() + start, offset - start);
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
