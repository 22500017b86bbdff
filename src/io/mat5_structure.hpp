#pragma once
// Structural check of a MATLAB level-5 .mat file before libmatio reads it. libmatio trusts the sizes its tags
// and dimension fields declare and allocates from them before reading a byte, and it reads an array's parts
// one after the other without bounding them by the array, so a corrupt or truncated file (a tag claiming
// gigabytes, dims of 10^10, an array whose parts run into the next variable) makes it ask for gigabytes.
// This walks the file's data elements (MAT-File Format, MathWorks, "Data Element Format" and "miMATRIX
// Format"; compressed elements inflated with zlib) and accepts only the exact layout libmatio expects: arrays
// and compressed arrays at the top level, and in each array its flags, dimensions, name and exactly the parts
// its class has, each holding as many values as the dimensions declare. Version 7.3 files (HDF5) are left to
// libmatio; level-4 files are refused.
#include <filesystem>

namespace glmbslam::io {

/// Throws InputError naming `path` and the first inconsistency found, or if the file is neither level 5 nor
/// 7.3 (level-4 files are not read); returns silently for a consistent level-5 file or a 7.3 file.
void check_mat5_structure(const std::filesystem::path& path);

}  // namespace glmbslam::io
