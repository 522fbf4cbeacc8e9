// The keys a page of docs/ lists in a table, for tests that hold a
// reader's keys to its documentation: the first column's `KEY` of each row
// of the table that follows the line "<!-- keys: NAME -->".
#pragma once

#include <algorithm>
#include <fstream>
#include <regex>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace hcosim::tests {

// docs/PAGE's table NAME, sorted. Throws std::runtime_error when the page
// or the table is missing.
inline std::vector<std::string> documented_keys(const std::string& page, const std::string& name) {
  const std::string path = std::string(HCOSIM_SOURCE_DIR) + "/docs/" + page;
  std::ifstream in(path);
  if (!in) throw std::runtime_error("no " + path);
  std::string line;
  while (std::getline(in, line) && line != "<!-- keys: " + name + " -->") {
  }
  if (!in) throw std::runtime_error(path + " has no table marked <!-- keys: " + name + " -->");
  std::vector<std::string> keys;
  const std::regex row("^\\| `([a-z_]+)` \\|.*");
  std::getline(in, line);  // the header
  std::getline(in, line);  // its rule
  for (std::smatch m; std::getline(in, line) && line.rfind('|', 0) == 0;)
    if (std::regex_match(line, m, row)) keys.push_back(m[1]);
  std::sort(keys.begin(), keys.end());
  return keys;
}

// The keys a reader allows, sorted, to compare with documented_keys().
inline std::vector<std::string> sorted(std::vector<std::string> keys) {
  std::sort(keys.begin(), keys.end());
  return keys;
}

}  // namespace hcosim::tests
