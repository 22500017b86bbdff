#include "io/mat_reader.hpp"

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <sstream>

#include <matio.h>

#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "io/mat5_structure.hpp"

namespace glmbslam::io {

namespace {

struct VarDeleter {
  void operator()(matvar_t* v) const {
    if (v != nullptr) Mat_VarFree(v);
  }
};
using VarPtr = std::unique_ptr<matvar_t, VarDeleter>;

std::string shape_string(const matvar_t* v) {
  std::ostringstream s;
  for (int i = 0; i < v->rank; ++i) s << (i > 0 ? "x" : "") << v->dims[i];
  return s.str();
}

std::string size_string(Eigen::Index n) {
  return n == kAnySize ? std::string("any") : std::to_string(n);
}

bool is_numeric_class(matio_classes c) {
  switch (c) {
    case MAT_C_DOUBLE:
    case MAT_C_SINGLE:
    case MAT_C_INT8:
    case MAT_C_UINT8:
    case MAT_C_INT16:
    case MAT_C_UINT16:
    case MAT_C_INT32:
    case MAT_C_UINT32:
    case MAT_C_INT64:
    case MAT_C_UINT64:
      return true;
    default:
      return false;
  }
}

const char* class_name(matio_classes c) {
  switch (c) {
    case MAT_C_CELL:
      return "cell";
    case MAT_C_STRUCT:
      return "struct";
    case MAT_C_OBJECT:
      return "object";
    case MAT_C_CHAR:
      return "char";
    case MAT_C_SPARSE:
      return "sparse";
    case MAT_C_DOUBLE:
      return "double";
    case MAT_C_SINGLE:
      return "single";
    case MAT_C_FUNCTION:
      return "function";
    default:
      return is_numeric_class(c) ? "integer" : "unknown";
  }
}

template <typename T>
void copy_column_major(const void* data, Eigen::MatrixXd& out) {
  const T* p = static_cast<const T*>(data);
  for (Eigen::Index i = 0; i < out.size(); ++i) out.data()[i] = static_cast<double>(p[i]);
}

/// Converts a read numeric matvar to a double matrix; `what` names the variable (or cell) in error messages.
Eigen::MatrixXd to_matrix(const std::string& file, const std::string& what, const matvar_t* v,
                          Eigen::Index rows, Eigen::Index cols, bool require_finite,
                          bool allow_empty_any_shape) {
  if (!is_numeric_class(v->class_type)) {
    throw InputError(
        file, "variable '" + what + "' must be a numeric matrix, found class " + class_name(v->class_type));
  }
  if (v->isComplex != 0) throw InputError(file, "variable '" + what + "' must be real, found complex values");
  if (v->rank != 2) {
    throw InputError(file, "variable '" + what + "' must be 2-D, found shape " + shape_string(v));
  }
  const auto r = static_cast<Eigen::Index>(v->dims[0]);
  const auto c = static_cast<Eigen::Index>(v->dims[1]);
  const bool empty = r == 0 || c == 0;
  if (empty && allow_empty_any_shape) {
    return Eigen::MatrixXd(rows == kAnySize ? 0 : rows, 0);
  }
  if ((rows != kAnySize && r != rows) || (cols != kAnySize && c != cols)) {
    throw InputError(file, "variable '" + what + "' must be " + size_string(rows) + "x" + size_string(cols) +
                               ", found " + shape_string(v));
  }
  Eigen::MatrixXd m(r, c);
  if (m.size() > 0) {
    if (v->data == nullptr) throw InputError(file, "variable '" + what + "' has no data");
    switch (v->class_type) {
      case MAT_C_DOUBLE:
        copy_column_major<double>(v->data, m);
        break;
      case MAT_C_SINGLE:
        copy_column_major<float>(v->data, m);
        break;
      case MAT_C_INT8:
        copy_column_major<std::int8_t>(v->data, m);
        break;
      case MAT_C_UINT8:
        copy_column_major<std::uint8_t>(v->data, m);
        break;
      case MAT_C_INT16:
        copy_column_major<std::int16_t>(v->data, m);
        break;
      case MAT_C_UINT16:
        copy_column_major<std::uint16_t>(v->data, m);
        break;
      case MAT_C_INT32:
        copy_column_major<std::int32_t>(v->data, m);
        break;
      case MAT_C_UINT32:
        copy_column_major<std::uint32_t>(v->data, m);
        break;
      case MAT_C_INT64:
        copy_column_major<std::int64_t>(v->data, m);
        break;
      case MAT_C_UINT64:
        copy_column_major<std::uint64_t>(v->data, m);
        break;
      default:
        break;
    }
  }
  if (require_finite && !m.allFinite()) {
    throw InputError(file, "variable '" + what + "' holds a NaN or infinite value");
  }
  return m;
}

}  // namespace

// Variables are read lazily and once: a lookup reads the file sequentially (Mat_VarReadNext, one pass that
// decodes each variable's header and data once) up to the requested variable, caching every variable it
// passes, so reading the variables in file order costs a single pass. A variable that pass cannot reach
// (Mat_VarReadNext stops early on a variable matio cannot read) is looked up by name as before.
struct MatFile::Handle {
  mat_t* mat = nullptr;
  std::vector<VarPtr> cache;     ///< variables read so far (sequentially, then by name)
  bool sequential_done = false;  ///< Mat_VarReadNext returned null: end of file, or an unreadable variable
  bool names_done = false;       ///< names_ lists every variable (a Mat_VarReadNextInfo pass was made)
  ~Handle() {
    if (mat != nullptr) Mat_Close(mat);
  }
  matvar_t* cached(const std::string& name) const {
    for (const auto& v : cache)
      if (v->name != nullptr && name == v->name) return v.get();
    return nullptr;
  }
  /// The variable from the cache or the sequential pass; null if the pass ends without it.
  matvar_t* find(const std::string& name) {
    if (matvar_t* v = cached(name)) return v;
    while (!sequential_done) {
      VarPtr v(Mat_VarReadNext(mat));
      if (!v) {
        sequential_done = true;
        break;
      }
      cache.push_back(std::move(v));
      if (cache.back()->name != nullptr && name == cache.back()->name) return cache.back().get();
    }
    return nullptr;
  }
};

MatFile::MatFile(const std::filesystem::path& path) : path_(path), handle_(std::make_unique<Handle>()) {
  if (!std::filesystem::is_regular_file(path)) throw InputError(path.string(), "file not found");
  check_mat5_structure(path);  // before libmatio allocates from the sizes the file declares
  handle_->mat = Mat_Open(path.string().c_str(), MAT_ACC_RDONLY);
  if (handle_->mat == nullptr) throw InputError(path.string(), "not a readable MATLAB .mat file");
}

MatFile::~MatFile() = default;
MatFile::MatFile(MatFile&&) noexcept = default;
MatFile& MatFile::operator=(MatFile&&) noexcept = default;

const std::vector<std::string>& MatFile::variable_names() const {
  if (!handle_->names_done) {
    // a separate pass over the headers; the sequential pass cannot resume after it
    handle_->sequential_done = true;
    Mat_Rewind(handle_->mat);
    names_.clear();
    while (matvar_t* info = Mat_VarReadNextInfo(handle_->mat)) {
      VarPtr guard(info);
      if (info->name != nullptr) names_.emplace_back(info->name);
    }
    Mat_Rewind(handle_->mat);
    handle_->names_done = true;
  }
  return names_;
}

bool MatFile::has(const std::string& name) const {
  if (!handle_->names_done && handle_->find(name) != nullptr) return true;
  for (const auto& n : variable_names()) {
    if (n == name) return true;
  }
  return false;
}

namespace {

/// The variable `name` of `handle` (owned by the handle), read once.
matvar_t* read_variable(MatFile::Handle& handle, const MatFile& file, const std::string& name) {
  if (matvar_t* v = handle.find(name)) return v;
  if (!file.has(name)) throw InputError(file.path().string(), "variable '" + name + "' is missing");
  VarPtr v(Mat_VarRead(handle.mat, name.c_str()));
  if (!v) throw InputError(file.path().string(), "variable '" + name + "' cannot be read");
  handle.cache.push_back(std::move(v));
  return handle.cache.back().get();
}

}  // namespace

Eigen::MatrixXd MatFile::read_matrix(const std::string& name, Eigen::Index rows, Eigen::Index cols,
                                     bool require_finite) const {
  const matvar_t* v = read_variable(*handle_, *this, name);
  return to_matrix(path_.string(), name, v, rows, cols, require_finite, false);
}

Eigen::VectorXd MatFile::read_vector(const std::string& name, Eigen::Index length,
                                     bool require_finite) const {
  const Eigen::MatrixXd m = read_matrix(name, kAnySize, kAnySize, require_finite);
  if (m.rows() != 1 && m.cols() != 1) {
    throw InputError(path_.string(), "variable '" + name + "' must be a vector (1xn or nx1), found " +
                                         std::to_string(m.rows()) + "x" + std::to_string(m.cols()));
  }
  if (length != kAnySize && m.size() != length) {
    throw InputError(path_.string(), "variable '" + name + "' must have " + std::to_string(length) +
                                         " elements, found " + std::to_string(m.size()));
  }
  return Eigen::Map<const Eigen::VectorXd>(m.data(), m.size());
}

double MatFile::read_scalar(const std::string& name) const {
  return read_matrix(name, 1, 1)(0, 0);
}

std::vector<Eigen::MatrixXd> MatFile::read_cell_matrices(const std::string& name, Eigen::Index rows,
                                                         Eigen::Index cell_count, bool require_finite) const {
  matvar_t* const v = read_variable(*handle_, *this, name);
  if (v->class_type != MAT_C_CELL) {
    throw InputError(path_.string(), "variable '" + name + "' must be a cell array, found class " +
                                         class_name(v->class_type));
  }
  if (v->rank != 2 || (v->dims[0] != 1 && v->dims[1] != 1 && v->dims[0] * v->dims[1] != 0)) {
    throw InputError(path_.string(),
                     "variable '" + name + "' must be a 1xn or nx1 cell array, found " + shape_string(v));
  }
  const std::size_t n = v->dims[0] * v->dims[1];
  if (cell_count != kAnySize && static_cast<Eigen::Index>(n) != cell_count) {
    throw InputError(path_.string(), "variable '" + name + "' must have " + std::to_string(cell_count) +
                                         " cells, found " + std::to_string(n));
  }
  std::vector<Eigen::MatrixXd> out;
  out.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    const matvar_t* cell = Mat_VarGetCell(v, static_cast<int>(i));
    const std::string what = name + "{" + std::to_string(i + 1) + "}";
    if (cell == nullptr) throw InputError(path_.string(), "variable '" + what + "' cannot be read");
    out.push_back(to_matrix(path_.string(), what, cell, rows, kAnySize, require_finite, true));
  }
  return out;
}

namespace {

matvar_t* create_double(const char* name, const Eigen::MatrixXd& m) {
  std::size_t dims[2] = {static_cast<std::size_t>(m.rows()), static_cast<std::size_t>(m.cols())};
  // MAT_F_DONT_COPY_DATA is not used: matio copies, so the Eigen storage may go away.
  return Mat_VarCreate(name, MAT_C_DOUBLE, MAT_T_DOUBLE, 2, dims, const_cast<double*>(m.data()), 0);
}

}  // namespace

void write_mat_file(const std::filesystem::path& path, const std::vector<MatVariable>& variables) {
  const std::filesystem::path tmp = temporary_path_for(path);
  mat_t* mat = Mat_CreateVer(tmp.string().c_str(), nullptr, MAT_FT_MAT5);
  if (mat == nullptr) throw InputError(path.string(), "cannot create the .mat file");
  bool ok = true;
  for (const auto& var : variables) {
    matvar_t* v = nullptr;
    if (!var.is_cell) {
      v = create_double(var.name.c_str(), var.matrix);
    } else {
      std::size_t dims[2] = {1, var.cells.size()};
      v = Mat_VarCreate(var.name.c_str(), MAT_C_CELL, MAT_T_CELL, 2, dims, nullptr, 0);
      for (std::size_t i = 0; v != nullptr && i < var.cells.size(); ++i) {
        matvar_t* c = create_double(nullptr, var.cells[i]);
        if (c == nullptr) {
          ok = false;
          break;
        }
        Mat_VarSetCell(v, static_cast<int>(i), c);  // the cell array takes ownership
      }
    }
    if (v == nullptr || Mat_VarWrite(mat, v, MAT_COMPRESSION_NONE) != 0) ok = false;
    if (v != nullptr) Mat_VarFree(v);
    if (!ok) break;
  }
  Mat_Close(mat);
  if (!ok) {
    std::remove(tmp.string().c_str());
    throw InputError(path.string(), "cannot write the .mat file");
  }
  commit_temporary(tmp, path);
}

}  // namespace glmbslam::io
