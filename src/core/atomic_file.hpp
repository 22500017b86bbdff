#pragma once
// Outputs are written to a temporary name in the same folder and renamed when complete, so no file that
// looks complete but is not is ever left behind.
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>

namespace glmbslam {

/// Temporary sibling path for `target` (same folder, so the final rename is atomic).
std::filesystem::path temporary_path_for(const std::filesystem::path& target);

/// Renames `temporary` onto `target`; throws InputError naming `target` on failure.
void commit_temporary(const std::filesystem::path& temporary, const std::filesystem::path& target);

/// Writes a text file atomically: `fill` writes the content into the stream; on any exception the
/// temporary file is removed and the exception propagates. Throws InputError if the file cannot be written.
void write_text_file_atomically(const std::filesystem::path& target,
                                const std::function<void(std::ostream&)>& fill);

/// Creates `dir` (and parents) if needed; throws InputError naming it if that fails or it is not writable.
void ensure_writable_directory(const std::filesystem::path& dir);

}  // namespace glmbslam
