#pragma once
// A small typed reader for MATLAB .mat files (v5/v7/v7.3 through libmatio): numeric matrices and cell arrays
// of numeric matrices, looked up by variable name, with shape and class checks. Every problem is an
// InputError that names the file and the variable. libmatio stays a private dependency of glmbslam_io.
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace glmbslam::io {

/// Any size in a shape check.
inline constexpr Eigen::Index kAnySize = -1;

class MatFile {
 public:
  /// Opens the file read-only; throws InputError if it is missing, not a MATLAB level-5 or 7.3 file, or its
  /// structure is inconsistent (corrupt or truncated: io/mat5_structure.hpp).
  explicit MatFile(const std::filesystem::path& path);
  ~MatFile();
  MatFile(const MatFile&) = delete;
  MatFile& operator=(const MatFile&) = delete;
  MatFile(MatFile&&) noexcept;
  MatFile& operator=(MatFile&&) noexcept;

  const std::filesystem::path& path() const { return path_; }
  /// Names of the variables in the file, in file order.
  const std::vector<std::string>& variable_names() const;
  bool has(const std::string& name) const;

  /// A real numeric 2-D matrix (any numeric class, converted to double). rows/cols = kAnySize accept any
  /// size. Throws InputError naming the variable if it is missing, not numeric, complex, sparse, not 2-D, of
  /// the wrong shape, or (when require_finite) holds a NaN or infinity.
  Eigen::MatrixXd read_matrix(const std::string& name, Eigen::Index rows = kAnySize,
                              Eigen::Index cols = kAnySize, bool require_finite = true) const;

  /// A numeric vector stored as 1×n or n×1 (length = kAnySize accepts any length, but not a matrix).
  Eigen::VectorXd read_vector(const std::string& name, Eigen::Index length = kAnySize,
                              bool require_finite = true) const;

  /// A scalar (1×1).
  double read_scalar(const std::string& name) const;

  /// A cell array (any 1×n or n×1 layout, returned in storage order) whose every element is a real numeric
  /// matrix with `rows` rows (kAnySize: any). An empty element (0×0 or rows×0) is returned as a rows×0 matrix
  /// (0×0 if rows is kAnySize). Optionally checks the number of cells.
  std::vector<Eigen::MatrixXd> read_cell_matrices(const std::string& name, Eigen::Index rows = kAnySize,
                                                  Eigen::Index cell_count = kAnySize,
                                                  bool require_finite = true) const;

 private:
  std::filesystem::path path_;
  mutable std::vector<std::string> names_;  ///< filled by the first variable_names()

 public:
  struct Handle;  ///< libmatio state and the variables read so far (mat_reader.cpp)

 private:
  std::unique_ptr<Handle> handle_;
};

/// A named variable for write_mat_file: a double matrix, or a cell array (1×n) of double matrices.
struct MatVariable {
  std::string name;
  Eigen::MatrixXd matrix;
  std::vector<Eigen::MatrixXd> cells;
  bool is_cell = false;

  static MatVariable matrix_variable(std::string name, Eigen::MatrixXd m) {
    MatVariable v;
    v.name = std::move(name);
    v.matrix = std::move(m);
    return v;
  }
  static MatVariable cell_variable(std::string name, std::vector<Eigen::MatrixXd> c) {
    MatVariable v;
    v.name = std::move(name);
    v.cells = std::move(c);
    v.is_cell = true;
    return v;
  }
};

/// Writes a MATLAB v5 file holding the given variables (atomically: temporary name, then rename).
/// Used by tests to build valid and broken inputs, and for small exports.
void write_mat_file(const std::filesystem::path& path, const std::vector<MatVariable>& variables);

}  // namespace glmbslam::io
