#include "report/profile_source.hpp"

#include <fstream>

namespace stickslip::tradeoff::report {

std::string repository_path(const std::string& path) {
  for (const char* root : {"lib/", "bench/", "sim_host/", "tests/"}) {
    const std::size_t at = path.rfind(std::string("/") + root);
    if (at != std::string::npos) return path.substr(at + 1);
  }
  const std::size_t slash = path.rfind('/');
  return slash == std::string::npos ? path : "<" + path.substr(slash + 1) + ">";
}

std::string source_line(const std::string& path, long number) {
  std::ifstream in(path);
  std::string line;
  for (long n = 1; n <= number && std::getline(in, line); ++n) {
  }
  line.erase(0, line.find_first_not_of(' '));
  if (line.size() > 100) line = line.substr(0, 97) + "...";
  return line;
}

std::string short_function(const std::string& name) {
  std::string out;
  int depth = 0;
  for (const char c : name.substr(0, name.find(" [clone"))) {
    if (c == '<' || c == '(') ++depth;
    if (depth == 0) out += c;
    if ((c == '>' || c == ')') && depth > 0) --depth;
  }
  const std::string qualifier = " const";
  if (out.size() > qualifier.size() &&
      out.compare(out.size() - qualifier.size(), qualifier.size(), qualifier) == 0) {
    out.resize(out.size() - qualifier.size());
  }
  const std::size_t space = out.rfind(' ');
  return space == std::string::npos ? out : out.substr(space + 1);
}

}  // namespace stickslip::tradeoff::report
