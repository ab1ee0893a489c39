// Atomic file output: every file furnace writes (reports, EXR images, JSON
// verdicts) goes through here, so a failed or interrupted write never leaves
// a half-written file under the target name (error tier 1, core/error.h).
//
// Protocol: a fresh temporary file is created in the target's directory
// (same file system, so the final rename is atomic) under a name no other
// writer uses (".<name>.tmp-<pid>-<counter>", created with O_EXCL, retried on
// a collision with a stale leftover), written, flushed to disk (fsync), and
// renamed over the target. On any failure the temporary file is removed and a
// furnace::Error naming the target file is thrown; the target is untouched.
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <string_view>

namespace furnace {

// Runs `write_to(temporary)` (which must create or truncate and fill the file
// at `temporary`, throwing on failure), then renames the temporary file over
// `path`. `what` names the kind of file in error messages ("report file",
// "OpenEXR file"). Throws furnace::Error, one sentence naming `path`; an
// Error thrown by write_to passes through unchanged.
void write_file_atomically(const std::filesystem::path& path,
                           const std::function<void(const std::filesystem::path& temporary)>& write_to,
                           std::string_view what = "file");

// Writes `text` to `path` atomically (the protocol above).
void write_text_file_atomically(const std::filesystem::path& path, const std::string& text,
                                std::string_view what = "file");

}  // namespace furnace
