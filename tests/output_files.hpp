// Reading back what the commands write: CSV tables by column name, a PNG's size from its header.
#pragma once

#include "test_support.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <map>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace pbs::test {

struct CsvRow {
  std::map<std::string, std::string> fields;
  double number(const std::string& column) const { return std::stod(fields.at(column)); }
};

struct CsvTable {
  std::string header;  // the first line as written
  std::vector<std::string> columns;
  std::vector<CsvRow> rows;
};

inline std::vector<std::string> splitCommas(const std::string& line) {
  std::vector<std::string> fields;
  std::istringstream in(line);
  for (std::string field; std::getline(in, field, ',');) fields.push_back(field);
  return fields;
}

// Every row is expected to be as wide as the header (a failure names the line).
inline CsvTable readCsv(const std::filesystem::path& file) {
  std::istringstream in(readFile(file));
  CsvTable table;
  std::getline(in, table.header);
  table.columns = splitCommas(table.header);
  for (std::string line; std::getline(in, line);) {
    const std::vector<std::string> fields = splitCommas(line);
    EXPECT_EQ(fields.size(), table.columns.size()) << line;
    CsvRow row;
    for (std::size_t i = 0; i < std::min(fields.size(), table.columns.size()); ++i)
      row.fields[table.columns[i]] = fields[i];
    table.rows.push_back(std::move(row));
  }
  return table;
}

// Width and height from a PNG's IHDR chunk (big-endian at bytes 16 and 20); {0, 0} when not a PNG.
inline std::pair<std::uint32_t, std::uint32_t> pngSize(const std::filesystem::path& file) {
  const std::string bytes = readFile(file);
  if (bytes.size() < 24 || bytes.compare(1, 3, "PNG") != 0) return {0, 0};
  const auto word = [&](std::size_t at) {
    std::uint32_t v = 0;
    for (std::size_t i = 0; i < 4; ++i) v = (v << 8) | std::uint8_t(bytes[at + i]);
    return v;
  };
  return {word(16), word(20)};
}

}  // namespace pbs::test
