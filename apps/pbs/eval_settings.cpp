// Parsing `--sweep KEY=V1,V2,…` into named settings.
#include "eval_settings.hpp"

#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdlib>
#include <set>
#include <sstream>

namespace pbs::cli {
namespace {

double parseNumber(const std::string& key, const std::string& value, double lo, double hi) {
  char* end = nullptr;
  const double number = std::strtod(value.c_str(), &end);
  if (value.empty() || end != value.c_str() + value.size() || !std::isfinite(number) || number < lo || number > hi) {
    std::ostringstream message;
    message << key << " needs a number in [" << lo << ", " << hi << "], got '" << value << "'";
    throw CLI::ValidationError("--sweep", message.str());
  }
  return number;
}

// Changes one option of `setting` (the LOD option, ordering or simplification `key` names).
void apply(const std::string& key, const std::string& value, EvalSetting& setting) {
  if (key == "overdraw") {
    setting.lod.overdraw = parseNumber(key, value, 1e-3, 1e4);
  } else if (key == "threshold") {
    setting.lod.threshold = parseNumber(key, value, 1e-3, 1e6);
  } else if (key == "point") {
    setting.lod.pointSize = float(parseNumber(key, value, 0.05, 64.0));
  } else if (key == "band") {
    setting.lod.band = parseNumber(key, value, 0.0, 10.0);
  } else if (key == "rule") {
    if (value != "coverage" && value != "packing")
      throw CLI::ValidationError("--sweep", "rule is coverage or packing, got '" + value + "'");
    setting.lod.prefixRule = value == "packing" ? PrefixRule::Packing : PrefixRule::Coverage;
  } else if (key == "ordering") {
    setting.ordering = parseOrdering(value);
    if (!setting.ordering)
      throw CLI::ValidationError("--sweep", "ordering is farthest, dart or random, got '" + value + "'");
  } else if (key == "simplify") {
    setting.simplify = parseNumber(key, value, 1e-6, 1.0);
  } else {
    throw CLI::ValidationError("--sweep", "unknown key '" + key + "' (one of " + sweepKeys() + ", or exact)");
  }
}

// "KEY=VALUE" split at its '=', or a ValidationError quoting `whole`.
std::pair<std::string, std::string> keyAndValue(const std::string& text, const std::string& whole) {
  const std::size_t equals = text.find('=');
  if (equals == std::string::npos || equals == 0 || equals + 1 == text.size())
    throw CLI::ValidationError("--sweep", "expected KEY=V1,V2,…, KEY=V+KEY=V or exact, got '" + whole + "'");
  return {text.substr(0, equals), text.substr(equals + 1)};
}

EvalSetting baselineSettingNamed(const std::string& name, const LodOptions& baseline) {
  return EvalSetting{.name = name, .exact = false, .lod = baseline, .ordering = {}, .simplify = {}};
}

// "KEY=V+KEY=V…": one setting with every change at once.
EvalSetting combinedSetting(const std::string& text, const LodOptions& baseline) {
  EvalSetting setting = baselineSettingNamed(text, baseline);
  std::istringstream parts(text);
  for (std::string part; std::getline(parts, part, '+');) {
    const auto [key, value] = keyAndValue(part, text);
    if (value.find(',') != std::string::npos)
      throw CLI::ValidationError("--sweep", "a combined setting takes one value per key, got '" + text + "'");
    apply(key, value, setting);
  }
  if (text.back() == '+') throw CLI::ValidationError("--sweep", "an empty part in '" + text + "'");
  return setting;
}

}  // namespace

std::string sweepKeys() { return "overdraw, threshold, point, band, rule, ordering, simplify"; }

std::vector<EvalSetting> parseSweep(const std::string& text, const LodOptions& baseline) {
  if (text == "exact") return {EvalSetting{.name = "exact", .exact = true, .lod = baseline, .ordering = {}, .simplify = {}}};
  if (text.find('+') != std::string::npos) return {combinedSetting(text, baseline)};
  const auto [key, list] = keyAndValue(text, text);
  std::vector<EvalSetting> settings;
  std::istringstream values(list);
  for (std::string value; std::getline(values, value, ',');) {
    EvalSetting setting = baselineSettingNamed(key + "=" + value, baseline);
    apply(key, value, setting);
    settings.push_back(std::move(setting));
  }
  if (settings.empty() || text.back() == ',')
    throw CLI::ValidationError("--sweep", "an empty value in '" + text + "'");
  return settings;
}

std::vector<std::string> defaultSweep(SurfelOrdering fileOrdering) {
  std::vector<std::string> sweeps = {"overdraw=1,2,4,8", "threshold=64,256", "point=1,4"};
  std::string orderings;
  for (SurfelOrdering o : {SurfelOrdering::Farthest, SurfelOrdering::Dart, SurfelOrdering::Random}) {
    if (o == fileOrdering) continue;
    if (!orderings.empty()) orderings.push_back(',');
    orderings.append(orderingName(o));
  }
  sweeps.push_back("ordering=" + orderings);
  sweeps.push_back("simplify=0.25,0.05,0.01");
  return sweeps;
}

std::vector<EvalSetting> evalSettings(const std::vector<std::string>& sweeps, const LodOptions& baseline) {
  std::vector<EvalSetting> settings = parseSweep("exact", baseline);
  std::set<std::string> names = {"exact"};
  for (const std::string& sweep : sweeps)
    for (EvalSetting& setting : parseSweep(sweep, baseline))
      if (names.insert(setting.name).second) settings.push_back(std::move(setting));
  return settings;
}

std::optional<std::size_t> baselineSetting(const std::vector<EvalSetting>& settings, const LodOptions& baseline) {
  const auto same = [&](const LodOptions& a) {
    return a.threshold == baseline.threshold && a.band == baseline.band && a.overdraw == baseline.overdraw &&
           a.pointSize == baseline.pointSize && a.prefixRule == baseline.prefixRule &&
           a.minSizeFactor == baseline.minSizeFactor;
  };
  const auto drawsSurfels = [](const EvalSetting& s) { return !s.exact && !s.simplify; };
  for (std::size_t i = 0; i < settings.size(); ++i)
    if (drawsSurfels(settings[i]) && !settings[i].ordering && same(settings[i].lod)) return i;
  for (std::size_t i = 0; i < settings.size(); ++i)
    if (drawsSurfels(settings[i])) return i;
  return std::nullopt;
}

}  // namespace pbs::cli
