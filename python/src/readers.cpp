// Recordings into numpy arrays: the host's readers and generators.
#include <pybind11/stl.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <optional>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "module.hpp"
#include "stickslip/can/codec.hpp"
#include "stickslip/host/io/candump_log.hpp"
#include "stickslip/host/run/recording_source.hpp"
#include "stickslip/host/signals/resample.hpp"
#include "stickslip/host/signals/seat_test_spectra.hpp"
#include "stickslip/host/signals/signal_generator.hpp"
#include "stickslip/metrics/den_hartog.hpp"

namespace stickslip::python {

std::string format_number(double value) {
  std::ostringstream text;
  text.precision(17);
  text << value;
  return text.str();
}

std::vector<double> time_line(std::size_t count, double dt_s) {
  std::vector<double> t;
  reserve_for_writing(t, count);
  for (std::size_t n = 0; n < count; ++n) t.push_back(static_cast<double>(n) * dt_s);
  return t;
}

py::dict signal_dict(std::vector<double>&& t, std::vector<double>&& a_u, double dt_s) {
  py::dict recording;
  recording["t"] = float64_array(std::move(t));
  recording["a_u"] = float64_array(std::move(a_u));
  recording["dt"] = dt_s;
  return recording;
}

std::vector<double> samples_from(const py::handle& values, const char* expected, const char* name) {
  auto array = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(values);
  if (!array) throw HostError(std::string(name) + ": expected " + expected);
  if (array.ndim() != 1) {
    throw HostError(std::string(name) + ": expected a 1-D array of samples, got " +
                    std::to_string(array.ndim()) + " dimensions");
  }
  const std::size_t count = static_cast<std::size_t>(array.shape(0));
  std::vector<double> samples;
  reserve_for_writing(samples, count);
  samples.assign(array.data(), array.data() + count);
  return samples;
}

host::SampledSignal read_recording_file(const std::string& path) {
  host::LoadedRecording loaded = host::read_recording(path, host::RecordingOptions{});
  host::require_force_as_read(path, loaded);
  host::SampledSignal& signal = loaded.segments.front();
  return std::move(signal);
}

namespace {

// The generators' messages name the command's flags ("--duration/--dt: ..."); generate() takes
// keyword arguments of the same names without the dashes ("duration/dt: ...").
std::string with_argument_names(const std::string& message) {
  const std::size_t head_end = message.find(": ");
  if (message.rfind("--", 0) != 0 || head_end == std::string::npos) return message;
  std::string head;
  for (std::size_t i = 0; i < head_end; ++i) {
    if (message.compare(i, 2, "--") == 0) {
      ++i;  // the dashes of a flag go; a dash inside its name becomes the keyword's '_'
    } else {
      head += message[i] == '-' ? '_' : message[i];
    }
  }
  return head + message.substr(head_end);
}

bool ends_with(const std::string& text, const char* suffix) {
  const std::size_t length = std::strlen(suffix);
  if (text.size() < length) return false;
  for (std::size_t i = 0; i < length; ++i) {
    const char c = text[text.size() - length + i];
    if ((c >= 'A' && c <= 'Z' ? static_cast<char>(c - 'A' + 'a') : c) != suffix[i]) return false;
  }
  return true;
}

// A recording as simulate() reads it (read_recording_file(), f_a included when the file has the
// column); a candump log (.log) as the SeatInput frames in it (valid CRC), one sample each,
// t = n dt.
py::dict read_recording(const py::object& path_like, double log_dt_s) {
  const std::string path = py::module_::import("os").attr("fspath")(path_like).cast<std::string>();
  if (ends_with(path, ".log")) {
    if (!(log_dt_s > 0.0) || !std::isfinite(log_dt_s)) {
      throw HostError("dt: must be a finite number > 0, got " + format_number(log_dt_s));
    }
    const std::vector<host::LoggedFrame> frames = host::read_candump_log(path);
    std::vector<double> a_u;
    std::uint64_t skipped = 0;
    for (const host::LoggedFrame& logged : frames) {
      const can::Frame& frame = logged.frame;
      if (frame.id != can::kSeatInput.id || frame.length != can::kPayloadLength ||
          !can::crc_ok(can::kSeatInput, frame.data)) {
        ++skipped;
        continue;
      }
      const can::Payload payload = can::decode_payload(frame.data);
      a_u.push_back(can::physical<double>(can::kSeatInput.signals[0], payload.words[0]));
    }
    if (a_u.size() < 2) throw HostError(path + ": fewer than 2 SeatInput frames");
    std::vector<double> t = time_line(a_u.size(), log_dt_s);
    py::dict recording = signal_dict(std::move(t), std::move(a_u), log_dt_s);
    recording["skipped_frames"] = skipped;
    return recording;
  }
  host::SampledSignal signal = read_recording_file(path);
  py::dict recording =
      signal_dict(std::move(signal.t_s), std::move(signal.a_u_m_per_s2), signal.dt_s);
  if (!signal.f_a_n.empty()) recording["f_a"] = float64_array(std::move(signal.f_a_n));
  return recording;
}

py::dict generate_samples(const std::string& kind, std::optional<double> rms, double duration_s,
                          double dt_s, std::uint64_t seed, double frequency_hz, double band_low_hz,
                          double band_high_hz) {
  std::vector<double> a_u;
  host::SpectrumSignalSpec spectrum;
  const host::TargetSpectrum* table = host::find_seat_test_spectrum(kind);
  if (table != nullptr || kind == "white") {
    if (table != nullptr) {
      spectrum.spectrum = *table;
    } else {
      if (!rms) throw HostError("rms: required for white");
      if (!std::isfinite(band_low_hz) || !(band_low_hz >= 0.0) || !std::isfinite(band_high_hz) ||
          !(band_high_hz > band_low_hz)) {
        throw HostError("band_low/band_high: need 0 <= low < high, got " +
                        format_number(band_low_hz) + " and " + format_number(band_high_hz));
      }
      spectrum.spectrum = host::white_noise_spectrum(band_low_hz, band_high_hz, 1.0);
    }
    spectrum.rms_m_per_s2 = rms.value_or(0.0);
    if (rms && !(*rms > 0.0))
      throw HostError("rms: must be a finite number > 0, got " + format_number(*rms));
    spectrum.duration_s = duration_s;
    spectrum.dt_s = dt_s;
    spectrum.seed = seed;
    host::validate(spectrum);
    py::gil_scoped_release release;
    a_u = host::generate_spectrum_signal(spectrum);
  } else {
    host::GeneratorSpec spec;
    if (!host::parse_signal_kind(kind, spec.kind)) {
      throw HostError("kind: unknown kind '" + kind +
                      "' (expected wideband, lorry, harmonic, white, EM1..EM9, IT1, IT4, AG2 or "
                      "AG3)");
    }
    if (!rms) throw HostError("rms: required for " + kind);
    spec.rms_m_per_s2 = *rms;
    spec.duration_s = duration_s;
    spec.dt_s = dt_s;
    spec.seed = seed;
    spec.frequency_hz = frequency_hz;
    host::validate(spec);
    py::gil_scoped_release release;
    a_u = host::generate_signal(spec);
  }
  std::vector<double> t = time_line(a_u.size(), dt_s);
  return signal_dict(std::move(t), std::move(a_u), dt_s);
}

py::dict generate(const std::string& kind, std::optional<double> rms, double duration_s,
                  double dt_s, std::uint64_t seed, double frequency_hz, double band_low_hz,
                  double band_high_hz) {
  try {
    return generate_samples(kind, rms, duration_s, dt_s, seed, frequency_hz, band_low_hz,
                            band_high_hz);
  } catch (const HostError& error) {
    throw HostError(with_argument_names(error.what()));
  }
}

// The CLI's `simulate --dt` on a uniform recording (host::resample_step(), libsoxr): the same
// samples for the same dt and new dt.
py::dict resample(const py::handle& a_u, double dt_s, double new_dt_s) {
  if (!(dt_s > 0.0) || !std::isfinite(dt_s)) {
    throw HostError("dt: must be a finite number > 0, got " + format_number(dt_s));
  }
  if (!(new_dt_s > 0.0) || !std::isfinite(new_dt_s)) {
    throw HostError("new_dt: must be a finite number > 0, got " + format_number(new_dt_s));
  }
  std::vector<double> samples = samples_from(a_u, "a 1-D array of samples (m/s^2)");
  if (samples.size() < 2) {
    throw HostError("a_u: resampling needs at least 2 samples, got " +
                    std::to_string(samples.size()));
  }
  for (std::size_t n = 0; n < samples.size(); ++n) {
    if (!std::isfinite(samples[n])) {
      throw HostError("a_u = " + format_number(samples[n]) + " at sample " + std::to_string(n) +
                      ": resampling needs finite samples");
    }
  }
  std::vector<double> resampled;
  {
    py::gil_scoped_release release;
    resampled = host::resample_step(samples, dt_s, new_dt_s);
  }
  if (resampled.size() < 2) {
    throw HostError("new_dt: " + format_number(new_dt_s) + " s leaves " +
                    std::to_string(resampled.size()) + " of the recording's " +
                    std::to_string(samples.size()) + " samples at dt = " + format_number(dt_s) +
                    " s (at least 2 are needed)");
  }
  std::vector<double> t = time_line(resampled.size(), new_dt_s);
  return signal_dict(std::move(t), std::move(resampled), new_dt_s);
}

}  // namespace

void bind_readers(py::module_& m) {
  m.def("read_recording", &read_recording, py::arg("path"), py::arg("dt") = 1e-3);
  m.def("resample", &resample, py::arg("a_u"), py::arg("dt"), py::arg("new_dt"));
  m.def("generate", &generate, py::arg("kind"), py::arg("rms"), py::arg("duration"), py::arg("dt"),
        py::arg("seed") = 1, py::arg("frequency") = 0.0, py::arg("band_low") = 0.5,
        py::arg("band_high") = 20.0);
  m.def("den_hartog_factor", &stickslip::den_hartog_factor, py::arg("ffk"), py::arg("mass"),
        py::arg("rms_u"));
}

}  // namespace stickslip::python
