// stickslip_stability_map [--coarse] [--output FILE]
// Scans the stability map (see stability_map.hpp), writes the Markdown report to FILE (default:
// standard output) and exits 1 if any accepted cell is unstable, 2 on a usage error.
#include <chrono>
#include <cstdio>
#include <cstring>
#include <string>

#include "stickslip/reliability/stability_map.hpp"

namespace {
void report_progress(double dt_s, std::size_t done) {
  std::fprintf(stderr, "stability map: dt = %g s done, %zu cells\n", dt_s, done);
}
}  // namespace

int main(int argc, char** argv) {
  using namespace stickslip::reliability;
  bool coarse = false;
  const char* output = nullptr;
  std::string command = "tools/stability-map.sh";
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--coarse") == 0) {
      coarse = true;
    } else if (std::strcmp(argv[i], "--output") == 0 && i + 1 < argc) {
      output = argv[++i];
    } else if (std::strcmp(argv[i], "--command") == 0 && i + 1 < argc) {
      command = argv[++i];  // the command to quote in the report
    } else {
      std::fprintf(stderr, "usage: %s [--coarse] [--output FILE] [--command TEXT]\n", argv[0]);
      return 2;
    }
  }
  const MapGrid grid = coarse ? coarse_grid() : full_grid();
  const auto start = std::chrono::steady_clock::now();
  const std::vector<Cell> cells = run_map(grid, report_progress);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const std::string md = markdown_report(grid, cells, command, seconds);
  if (output == nullptr) {
    std::fputs(md.c_str(), stdout);
  } else {
    std::FILE* file = std::fopen(output, "w");
    if (file == nullptr || std::fputs(md.c_str(), file) < 0 || std::fclose(file) != 0) {
      std::fprintf(stderr, "stability map: cannot write %s\n", output);
      return 2;
    }
  }
  int unstable = 0;
  for (const Cell& c : cells) {
    if (c.verdict != Verdict::unstable) continue;
    if (unstable++ < 20)
      std::fprintf(stderr, "UNSTABLE %s: %s\n", describe(c).c_str(), c.reason.c_str());
  }
  std::fprintf(stderr, "stability map: %zu cells, %d unstable, %.1f s\n", cells.size(), unstable,
               seconds);
  return unstable == 0 ? 0 : 1;
}
