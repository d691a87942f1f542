// How the profile names where instructions go: repository-relative files, the source text of a
// line, short function names.
#pragma once

#include <string>

namespace stickslip::tradeoff::report {

// "lib/include/stickslip/models/oscillator.hpp" from the absolute path in the dump.
std::string repository_path(const std::string& path);
// Line `number` of the file, leading blanks removed, cut at 100 characters.
std::string source_line(const std::string& path, long number);
// The qualified name without return type, template arguments, parameters and clone suffixes.
std::string short_function(const std::string& name);

}  // namespace stickslip::tradeoff::report
