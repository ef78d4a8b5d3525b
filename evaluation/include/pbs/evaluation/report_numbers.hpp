// Small numeric helpers every report shares (the evaluation's files, the commands' output): counts with
// thousands separators, elapsed time, medians, CSV numbers, JSON for values that may be infinite.
#pragma once

#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <initializer_list>
#include <string>
#include <string_view>
#include <vector>

namespace pbs {

// 1234567 → "1,234,567": triangle counts of billions must be readable at a glance.
inline std::string withThousands(std::uint64_t value) {
  const std::string digits = std::to_string(value);
  std::string grouped;
  for (std::size_t i = 0; i < digits.size(); ++i) {
    if (i > 0 && (digits.size() - i) % 3 == 0) grouped += ',';
    grouped += digits[i];
  }
  return grouped;
}

inline double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// The median of `values` (the mean of the middle two for an even count); 0 for none.
inline double median(std::vector<double> values) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

// A number as the CSV files write it: whole numbers in full (%.9g would round a billion triangles),
// others %.9g, "inf" for the PSNR of identical images.
inline std::string csvNumber(double value) {
  if (std::isinf(value)) return value > 0 ? "inf" : "-inf";
  char text[32];
  const bool count = value == std::floor(value) && std::abs(value) < 1e15;
  std::snprintf(text, sizeof text, count ? "%.0f" : "%.9g", value);
  return text;
}

// A PSNR as the text tables print it: two decimals, "inf" for identical images.
inline std::string decibelText(double psnr) {
  if (!std::isfinite(psnr)) return "inf";
  char text[32];
  std::snprintf(text, sizeof text, "%.2f", psnr);
  return text;
}

// Appends one CSV line: `first`, then every value as csvNumber writes it.
inline void appendCsvLine(std::string& csv, std::string_view first, std::initializer_list<double> values) {
  csv.append(first);
  for (double value : values) csv.append(",").append(csvNumber(value));
  csv.push_back('\n');
}

// JSON cannot hold infinities (a PSNR of identical images): they are written as null.
inline nlohmann::json finiteOrNull(double value) {
  return std::isfinite(value) ? nlohmann::json(value) : nlohmann::json();
}

}  // namespace pbs
