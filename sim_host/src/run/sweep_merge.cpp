// stickslip merge: the shard files of a sweep joined into the file one unsharded run writes,
// after checking that they are all the shards of the same sweep, each once.
#include <fmt/format.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <map>

#include "stickslip/host/error.hpp"
#include "stickslip/host/io/output_file.hpp"
#include "stickslip/host/run/sweep.hpp"

namespace stickslip::host {

void merge_sweep_shards(const std::vector<std::string>& shard_paths,
                        const std::string& output_path) {
  if (shard_paths.empty()) throw UsageError("merge: no shard files given");
  std::map<std::uint64_t, std::string> rows;  // point -> the row's text
  std::vector<bool> seen_shard;
  unsigned count = 0;
  std::uint64_t points = 0;
  std::string config;
  std::vector<std::string> shard_file;  // by shard index - 1: where each point should be
  for (const std::string& path : shard_paths) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw HostError(path + ": cannot open: " + std::strerror(errno));
    std::string tag, header, line;
    if (!std::getline(in, tag) || tag.rfind(kShardTag, 0) != 0) {
      throw HostError(path + ":1: not a sweep shard (no '" + std::string(kShardTag) + "I/N' line)");
    }
    unsigned index = 0, n = 0;
    unsigned long long total = 0;
    char hash[32] = {};
    if (std::sscanf(tag.c_str() + std::strlen(kShardTag), "%u/%u points %llu config %16s", &index,
                    &n, &total, hash) != 4 ||
        n == 0 || index < 1 || index > n) {
      throw HostError(path + ":1: malformed shard line '" + tag + "'");
    }
    if (seen_shard.empty()) {
      count = n;
      points = total;
      config = hash;
      seen_shard.assign(n, false);
      shard_file.assign(n, std::string());
    } else if (n != count || total != points || config != hash) {
      throw HostError(
          fmt::format("{}:1: shard of another sweep ({}/{} points {} config {}; the "
                      "first file has N = {}, {} points, config {})",
                      path, index, n, total, hash, count, points, config));
    }
    if (seen_shard[index - 1])
      throw HostError(fmt::format("{}: shard {}/{} given twice", path, index, n));
    seen_shard[index - 1] = true;
    shard_file[index - 1] = path;
    if (!std::getline(in, header) || header != kSweepHeader)
      throw HostError(path + ":2: not the sweep header");
    std::size_t line_number = 2;
    while (std::getline(in, line)) {
      ++line_number;
      if (line.empty()) continue;
      const std::uint64_t point = std::strtoull(line.c_str(), nullptr, 10);
      if (line.find(',') == std::string::npos || point >= points || point % n != index - 1) {
        throw HostError(fmt::format("{}:{}: point '{}' does not belong to shard {}/{} of {} points",
                                    path, line_number, line.substr(0, line.find(',')), index, n,
                                    points));
      }
      if (!rows.emplace(point, line).second)
        throw HostError(fmt::format("{}:{}: point {} appears twice", path, line_number, point));
    }
  }
  for (unsigned i = 0; i < count; ++i) {
    if (!seen_shard[i]) throw HostError(fmt::format("merge: shard {}/{} is missing", i + 1, count));
  }
  if (rows.size() != points) {
    std::uint64_t missing = 0;
    while (rows.count(missing) != 0) ++missing;
    throw HostError(fmt::format("{}: point {} of shard {}/{} is missing ({} of {} points present)",
                                shard_file[missing % count], missing, missing % count + 1, count,
                                rows.size(), points));
  }
  AtomicOutputFile file(output_path);
  CsvWriter writer(file);
  writer.text(kSweepHeader);
  writer.text("\n");
  for (const auto& entry : rows) {
    writer.text(entry.second);
    writer.text("\n");
  }
  writer.flush();
  file.commit();
}

}  // namespace stickslip::host
