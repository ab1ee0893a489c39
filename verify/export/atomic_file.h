// Writing an export without ever leaving a half-written file behind.
#pragma once

#include <filesystem>
#include <string>

namespace furnace::exporter {

// Writes `contents` to a temporary file in the destination's directory and
// renames it over `path` once complete and closed, so a reader sees either the
// old file or the whole new one, and a failure leaves no file at all.
// Throws furnace::Error naming the file on any failure.
void write_file_atomically(const std::filesystem::path& path, const std::string& contents);

}  // namespace furnace::exporter
