// parseViewRequest: every parameter's name, range and choices in one table-like function.
#include "view_request.hpp"

#include <pbs/raster/value_names.hpp>

#include <cctype>
#include <charconv>
#include <cmath>
#include <functional>
#include <stdexcept>

namespace pbs::cli {
namespace {

constexpr ValueNames<ViewShow, 7> kShowNames{{{{ViewShow::Surfels, "surfels"},
                                               {ViewShow::Exact, "exact"},
                                               {ViewShow::Embree, "embree"},
                                               {ViewShow::Difference, "difference"},
                                               {ViewShow::Flip, "flip"},
                                               {ViewShow::Source, "source"},
                                               {ViewShow::Prefix, "prefix"}}}};
constexpr ValueNames<ViewEncoding, 2> kEncodingNames{{{{ViewEncoding::Jpeg, "jpeg"}, {ViewEncoding::Png, "png"}}}};

[[noreturn]] void refuse(const std::string& name, const std::string& value, const std::string& expected) {
  throw std::invalid_argument(name + ": expected " + expected + ", got '" + value.substr(0, 64) + "'");
}

double number(const std::string& name, const std::string& value, double lo, double hi) {
  double parsed = 0.0;
  const char* end = value.data() + value.size();
  const auto [stop, error] = std::from_chars(value.data(), end, parsed);
  const std::string range = "a number in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]";
  if (error != std::errc() || stop != end || !std::isfinite(parsed) || parsed < lo || parsed > hi)
    refuse(name, value, range);
  return parsed;
}

std::uint64_t whole(const std::string& name, const std::string& value, std::uint64_t lo, std::uint64_t hi) {
  std::uint64_t parsed = 0;
  const char* end = value.data() + value.size();
  const auto [stop, error] = std::from_chars(value.data(), end, parsed);
  if (error != std::errc() || stop != end || parsed < lo || parsed > hi)
    refuse(name, value, "a whole number in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
  return parsed;
}

template <typename Enum, std::size_t N>
Enum choice(const std::string& name, const std::string& value, const ValueNames<Enum, N>& names,
            const std::string& expected) {
  const std::optional<Enum> parsed = names.parse(value);
  if (!parsed) refuse(name, value, expected);
  return *parsed;
}

bool isClientName(const std::string& value) {
  if (value.empty() || value.size() > 64) return false;
  for (char c : value)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '-' && c != '_') return false;
  return true;
}

// World coordinates: finite and far below where a camera's doubles lose the scene.
constexpr double kMaxCoordinate = 1e15;

}  // namespace

const char* viewShowName(ViewShow show) { return kShowNames.name(show).data(); }

ViewRequest parseViewRequest(const std::multimap<std::string, std::string>& parameters, const ViewRequest& defaults) {
  ViewRequest request = defaults;
  using Setter = std::function<void(const std::string&, const std::string&)>;
  const std::map<std::string, Setter> setters = {
      {"client",
       [&](const std::string& name, const std::string& value) {
         if (!isClientName(value)) refuse(name, value, "1 to 64 letters, digits, '-' or '_'");
         request.client = value;
       }},
      {"seq", [&](auto& name, auto& value) { request.sequence = whole(name, value, 0, UINT64_MAX); }},
      {"w", [&](auto& name, auto& value) { request.width = std::uint32_t(whole(name, value, 16, kMaxViewWidth)); }},
      {"h", [&](auto& name, auto& value) { request.height = std::uint32_t(whole(name, value, 16, kMaxViewHeight)); }},
      {"tx", [&](auto& name, auto& value) { request.target.x = number(name, value, -kMaxCoordinate, kMaxCoordinate); }},
      {"ty", [&](auto& name, auto& value) { request.target.y = number(name, value, -kMaxCoordinate, kMaxCoordinate); }},
      {"tz", [&](auto& name, auto& value) { request.target.z = number(name, value, -kMaxCoordinate, kMaxCoordinate); }},
      {"az", [&](auto& name, auto& value) { request.orbit.azimuthDegrees = number(name, value, -1e6, 1e6); }},
      {"el", [&](auto& name, auto& value) { request.orbit.elevationDegrees = number(name, value, -90, 90); }},
      {"dist", [&](auto& name, auto& value) { request.orbit.distance = number(name, value, 1e-6, 1e6); }},
      {"show",
       [&](auto& name, auto& value) {
         request.show = choice(name, value, kShowNames, "surfels, exact, embree, difference, flip, source or prefix");
       }},
      {"samples",
       [&](auto& name, auto& value) {
         const std::uint64_t samples = whole(name, value, 1, 64);
         if (samples != 1 && samples != 4 && samples != 16 && samples != 64) refuse(name, value, "1, 4, 16 or 64");
         request.samples = std::uint32_t(samples);
       }},
      {"format",
       [&](auto& name, auto& value) { request.encoding = choice(name, value, kEncodingNames, "jpeg or png"); }},
      {"threshold", [&](auto& name, auto& value) { request.lod.threshold = number(name, value, 1, 16384); }},
      {"overdraw", [&](auto& name, auto& value) { request.lod.overdraw = number(name, value, 0.25, 256); }},
      {"splat",
       [&](auto& name, auto& value) {
         const std::optional<SplatMode> splat = splatModeFromName(value);
         if (!splat) refuse(name, value, "blend or nearest");
         request.lod.splat = *splat;
       }},
      {"point", [&](auto& name, auto& value) { request.lod.pointSize = float(number(name, value, 0, 64)); }},
      // 0 turns a budget off: the thresholds decide.
      {"budget",
       [&](auto& name, auto& value) { request.lod.budget = LodBudget::primitives(number(name, value, 0, 1e10)); }},
      {"node", [&](auto& name, auto& value) { request.node = std::uint32_t(whole(name, value, 0, INT32_MAX)); }},
      {"prefix", [&](auto& name, auto& value) { request.prefix = std::uint32_t(whole(name, value, 1, UINT32_MAX)); }},
      {"x", [&](auto& name, auto& value) { request.x = std::uint32_t(whole(name, value, 0, kMaxViewWidth - 1)); }},
      {"y", [&](auto& name, auto& value) { request.y = std::uint32_t(whole(name, value, 0, kMaxViewHeight - 1)); }},
      {"budget_ms",
       [&](auto& name, auto& value) { request.lod.budget = LodBudget::seconds(number(name, value, 0, 1e5) / 1e3); }},
  };
  std::map<std::string, int> seen;
  for (const auto& [name, value] : parameters) {
    const auto setter = setters.find(name);
    if (setter == setters.end()) throw std::invalid_argument("unknown parameter '" + name.substr(0, 64) + "'");
    if (++seen[name] > 1) throw std::invalid_argument(name + ": given more than once");
    setter->second(name, value);
  }
  if (request.lod.pointSize > 0.0f && request.lod.splat != SplatMode::Nearest)
    throw std::invalid_argument("point: a fixed point size is for splat=nearest (0 sizes discs from the prefix)");
  if (seen.count("budget") && seen.count("budget_ms")) throw std::invalid_argument("budget and budget_ms: give one");
  if (request.show == ViewShow::Prefix && (!request.node || !seen.count("prefix")))
    throw std::invalid_argument("show=prefix: needs node and prefix");
  if (request.x >= request.width || request.y >= request.height)
    throw std::invalid_argument("x, y: outside the " + std::to_string(request.width) + "x" +
                                std::to_string(request.height) + " frame");
  return request;
}

}  // namespace pbs::cli
