#pragma once
// Structural check of a MATLAB level-5 .mat file before libmatio reads it. libmatio trusts the sizes its tags
// and dimension fields declare and allocates from them before reading a byte, so a corrupt or truncated file
// (a tag claiming gigabytes, dims of 10^10) makes it ask for gigabytes. This walks the file's data elements
// (MAT-File Format, MathWorks, "Data Element Format"; compressed elements inflated with zlib) and rejects any
// element that declares more bytes than its container holds, or an array declaring more elements than its
// data can store. Version 7.3 files (HDF5) are left to libmatio; level-4 files are refused.
#include <filesystem>

namespace glmbslam::io {

/// Throws InputError naming `path` and the first inconsistency found, or if the file is neither level 5 nor
/// 7.3 (level-4 files are not read); returns silently for a consistent level-5 file or a 7.3 file.
void check_mat5_structure(const std::filesystem::path& path);

}  // namespace glmbslam::io
