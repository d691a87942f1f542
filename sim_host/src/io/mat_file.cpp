#include "stickslip/host/io/mat_file.hpp"

#include <fmt/format.h>
#include <matio.h>

#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <memory>

#include "stickslip/host/error.hpp"

namespace stickslip::host {
namespace {

struct MatCloser {
  void operator()(mat_t* file) const noexcept { Mat_Close(file); }
};
struct VarFreer {
  void operator()(matvar_t* variable) const noexcept { Mat_VarFree(variable); }
};
using MatFile = std::unique_ptr<mat_t, MatCloser>;
using MatVar = std::unique_ptr<matvar_t, VarFreer>;

template <typename T>
void append_as_double(const void* data, std::size_t count, std::vector<double>& out) {
  const T* values = static_cast<const T*>(data);
  for (std::size_t i = 0; i < count; ++i) out.push_back(static_cast<double>(values[i]));
}

// The variable as a vector of doubles (a row, a column or a scalar); nullopt-like empty vector
// with `present` false when the variable is absent.
std::vector<double> read_vector(mat_t* file, const std::string& path, const char* name,
                                bool& present) {
  MatVar variable(Mat_VarRead(file, name));
  present = variable != nullptr;
  std::vector<double> out;
  if (!present) return out;
  const matvar_t& v = *variable;
  if (v.isComplex != 0 || v.data == nullptr) {
    throw HostError(fmt::format("{}: variable '{}' must be a real numeric array", path, name));
  }
  std::size_t count = 1;
  int non_singleton = 0;
  for (int d = 0; d < v.rank; ++d) {
    count *= v.dims[d];
    if (v.dims[d] > 1) ++non_singleton;
  }
  if (non_singleton > 1) {
    throw HostError(
        fmt::format("{}: variable '{}' must be a vector, got a {}-D array with {} "
                    "non-singleton dimensions",
                    path, name, v.rank, non_singleton));
  }
  out.reserve(count);
  switch (v.class_type) {
    case MAT_C_DOUBLE:
      append_as_double<double>(v.data, count, out);
      break;
    case MAT_C_SINGLE:
      append_as_double<float>(v.data, count, out);
      break;
    case MAT_C_INT8:
      append_as_double<std::int8_t>(v.data, count, out);
      break;
    case MAT_C_UINT8:
      append_as_double<std::uint8_t>(v.data, count, out);
      break;
    case MAT_C_INT16:
      append_as_double<std::int16_t>(v.data, count, out);
      break;
    case MAT_C_UINT16:
      append_as_double<std::uint16_t>(v.data, count, out);
      break;
    case MAT_C_INT32:
      append_as_double<std::int32_t>(v.data, count, out);
      break;
    case MAT_C_UINT32:
      append_as_double<std::uint32_t>(v.data, count, out);
      break;
    case MAT_C_INT64:
      append_as_double<std::int64_t>(v.data, count, out);
      break;
    case MAT_C_UINT64:
      append_as_double<std::uint64_t>(v.data, count, out);
      break;
    default:
      throw HostError(
          fmt::format("{}: variable '{}' must be numeric (double, single or integer)", path, name));
  }
  for (std::size_t i = 0; i < out.size(); ++i) {
    if (!std::isfinite(out[i])) {
      throw HostError(fmt::format("{}: variable '{}' element {} is not finite", path, name, i + 1));
    }
  }
  return out;
}

bool has_mat_extension(const std::string& path) {
  if (path.size() < 4) return false;
  std::string tail = path.substr(path.size() - 4);
  for (char& c : tail) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return tail == ".mat";
}

}  // namespace

SampledSignal read_signal_mat(const std::string& path, MatTimes times) {
  MatFile file(Mat_Open(path.c_str(), MAT_ACC_RDONLY));
  if (!file) throw HostError(path + ": cannot open as a MATLAB .mat file");
  bool has_a_u = false, has_t = false, has_dt = false;
  SampledSignal signal;
  signal.a_u_m_per_s2 = read_vector(file.get(), path, "a_u", has_a_u);
  if (!has_a_u) throw HostError(path + ": no variable 'a_u' (the acceleration, m/s^2)");
  const std::size_t n = signal.a_u_m_per_s2.size();
  if (n < 2)
    throw HostError(fmt::format("{}: 'a_u' has {} samples; at least 2 are needed", path, n));
  signal.t_s = read_vector(file.get(), path, "t", has_t);
  if (has_t) {
    if (signal.t_s.size() != n) {
      throw HostError(
          fmt::format("{}: 't' has {} samples but 'a_u' has {}", path, signal.t_s.size(), n));
    }
    const double first_step = signal.t_s[1] - signal.t_s[0];
    for (std::size_t i = 1; i < n; ++i) {
      const double step = signal.t_s[i] - signal.t_s[i - 1];
      if (!(step > 0.0)) {
        throw HostError(fmt::format("{}: 't' must increase, element {} is {} after {}", path, i + 1,
                                    signal.t_s[i], signal.t_s[i - 1]));
      }
      if (times == MatTimes::uniform &&
          std::fabs(step - first_step) > kUniformStepTolerance * first_step) {
        throw HostError(
            fmt::format("{}: 't' is not uniform at element {}: step {} s against the "
                        "first step {} s (stickslip inspect {} suggests the flags)",
                        path, i + 1, step, first_step, path));
      }
    }
    signal.dt_s = (signal.t_s.back() - signal.t_s.front()) / static_cast<double>(n - 1);
    return signal;
  }
  const std::vector<double> dt = read_vector(file.get(), path, "dt", has_dt);
  if (!has_dt) throw HostError(path + ": neither 't' (s) nor 'dt' (s) is in the file");
  if (dt.size() != 1 || !(dt[0] > 0.0)) {
    throw HostError(path + ": 'dt' must be one positive number (s)");
  }
  signal.dt_s = dt[0];
  signal.t_s.resize(n);
  for (std::size_t i = 0; i < n; ++i) signal.t_s[i] = static_cast<double>(i) * dt[0];
  return signal;
}

namespace {

void write_mat_variables(const std::string& path, const std::string& temporary,
                         const SampledSignal& signal) {
  MatFile file(Mat_CreateVer(temporary.c_str(), nullptr, MAT_FT_MAT5));
  if (!file) throw HostError(path + ": cannot create the .mat file");
  const auto write = [&](const char* name, const std::vector<double>& values) {
    std::size_t dims[2] = {values.size(), 1};
    // matio does not write through the pointer (MAT_F_DONT_COPY_DATA is not needed for writing).
    MatVar variable(Mat_VarCreate(name, MAT_C_DOUBLE, MAT_T_DOUBLE, 2, dims,
                                  const_cast<double*>(values.data()), MAT_F_DONT_COPY_DATA));
    if (!variable || Mat_VarWrite(file.get(), variable.get(), MAT_COMPRESSION_NONE) != 0) {
      throw HostError(fmt::format("{}: cannot write variable '{}'", path, name));
    }
  };
  write("t", signal.t_s);
  write("a_u", signal.a_u_m_per_s2);
}

}  // namespace

void write_signal_mat(const std::string& path, const SampledSignal& signal) {
  // Written beside the target and renamed over it: a failure leaves neither a partial file nor a
  // changed one.
  const std::string temporary = path + ".partial";
  try {
    write_mat_variables(path, temporary, signal);
  } catch (...) {
    std::remove(temporary.c_str());
    throw;
  }
  if (std::rename(temporary.c_str(), path.c_str()) != 0) {
    std::remove(temporary.c_str());
    throw HostError(path + ": cannot write the .mat file (rename failed)");
  }
}

SampledSignal read_signal_file(const std::string& path) {
  return has_mat_extension(path) ? read_signal_mat(path) : read_signal_csv(path);
}

}  // namespace stickslip::host
