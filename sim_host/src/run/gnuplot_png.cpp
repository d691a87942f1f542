#include "stickslip/host/run/gnuplot_png.hpp"

#include <fmt/format.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <system_error>

#include "stickslip/host/error.hpp"

namespace stickslip::host {

bool gnuplot_available() {
  return std::system("command -v gnuplot >/dev/null 2>&1") == 0;
}

void draw_png(const std::string& script, const std::string& data_path,
              const std::string& image_path, const std::string& png_path, const char* what) {
  const std::string command = "gnuplot -e \"" + script + "\" 2>&1";
  std::FILE* pipe = popen(command.c_str(), "r");
  std::string output;
  int status = -1;
  if (pipe != nullptr) {
    char buffer[256];
    while (std::fgets(buffer, sizeof buffer, pipe) != nullptr) output += buffer;
    status = pclose(pipe);
  }
  std::error_code ignored;
  std::filesystem::remove(data_path, ignored);
  if (status != 0) {
    std::filesystem::remove(image_path, ignored);
    throw HostError(fmt::format("{}: gnuplot could not draw {}: {}", png_path, what,
                                output.substr(0, output.find('\n'))));
  }
  std::error_code error;
  std::filesystem::rename(image_path, png_path, error);
  if (error) {
    std::filesystem::remove(image_path, ignored);
    throw HostError(fmt::format("{}: {}", png_path, error.message()));
  }
}

}  // namespace stickslip::host
