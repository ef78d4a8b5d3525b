// Parsing `--peers` and `--sweep KEY=V1,V2,…` into named settings.
#include "pbs/evaluation/eval_settings.hpp"

#include <pbs/raster/supersampling.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <optional>
#include <sstream>
#include <stdexcept>

namespace pbs {
namespace {

double parseNumber(const std::string& option, const std::string& key, const std::string& value, double lo, double hi) {
  char* end = nullptr;
  const double number = std::strtod(value.c_str(), &end);
  if (value.empty() || end != value.c_str() + value.size() || !std::isfinite(number) || number < lo || number > hi) {
    std::ostringstream message;
    message << key << " needs a number in [" << lo << ", " << hi << "], got '" << value << "'";
    throw SweepError(option, message.str());
  }
  return number;
}

std::uint32_t parseSamples(const std::string& option, const std::string& key, const std::string& value) {
  const double samples = parseNumber(option, key, value, 1.0, 256.0);
  if (samples != std::floor(samples) || !isSupportedSampleCount(std::uint32_t(samples)))
    throw SweepError(option, key + " takes 1, 4, 16, 64 or 256 samples per pixel, got '" + value + "'");
  return std::uint32_t(samples);
}

// Changes one option of `setting` (the renderer, LOD option, ordering or simplification `key` names).
void apply(const std::string& option, const std::string& key, const std::string& value, EvalSetting& setting) {
  if (key == "embree" || key == "exact") {
    setting.mode = key == "embree" ? RenderMode::Embree : RenderMode::Exact;
    setting.samples = parseSamples(option, key, value);
  } else if (key == "overdraw") {
    setting.lod.overdraw = parseNumber(option, key, value, 1e-3, 1e4);
  } else if (key == "threshold") {
    setting.lod.threshold = parseNumber(option, key, value, 1e-3, 1e6);
  } else if (key == "primitives") {
    setting.lod.budget = LodBudget::primitives(parseNumber(option, key, value, 1.0, 1e12));
  } else if (key == "ms") {
    // The limit alone: whether it may lower the resolution is the command's (--budget-resolution).
    setting.lod.budget.limit = parseNumber(option, key, value, 1e-3, 1e6) / 1e3;
    setting.lod.budget.unit = BudgetUnit::Seconds;
  } else if (key == "point") {
    setting.lod.pointSize = float(parseNumber(option, key, value, 0.0, 64.0));
  } else if (key == "splat") {
    const std::optional<SplatMode> mode = splatModeFromName(value);
    if (!mode) throw SweepError(option, "splat is blend or nearest, got '" + value + "'");
    setting.lod.splat = *mode;
  } else if (key == "cull") {
    setting.lod.backFaceCosine = float(parseNumber(option, key, value, -1.0, 1.0));
  } else if (key == "gain") {
    setting.lod.coverageGain = float(parseNumber(option, key, value, 0.1, 10.0));
  } else if (key == "exhausted") {
    if (value != "descend" && value != "grow")
      throw SweepError(option, "exhausted is descend or grow, got '" + value + "'");
    setting.lod.descendExhausted = value == "descend";
  } else if (key == "rays") {
    if (value != "descend" && value != "keep") throw SweepError(option, "rays is descend or keep, got '" + value + "'");
    setting.lod.descendWhereRaysCheaper = value == "descend";
  } else if (key == "rays-preference") {
    setting.lod.raysPreference = parseNumber(option, key, value, 0.01, 100.0);
  } else if (key == "rays-near-share") {
    setting.lod.raysNearShare = parseNumber(option, key, value, 0.0, 1.0);
  } else if (key == "band") {
    setting.lod.band = parseNumber(option, key, value, 0.0, 10.0);
  } else if (key == "rule") {
    if (value != "coverage" && value != "packing")
      throw SweepError(option, "rule is coverage or packing, got '" + value + "'");
    setting.lod.prefixRule = value == "packing" ? PrefixRule::Packing : PrefixRule::Coverage;
  } else if (key == "geometry") {
    const std::optional<GeometryDrawer> drawer = geometryDrawerFromName(value);
    if (!drawer) throw SweepError(option, "geometry is raster, rays or auto, got '" + value + "'");
    setting.lod.geometry = *drawer;
  } else if (key == "ordering") {
    setting.ordering = parseOrdering(value);
    if (!setting.ordering) throw SweepError(option, "ordering is farthest, dart or random, got '" + value + "'");
  } else if (key == "simplify") {
    setting.mode = RenderMode::Simplified;
    setting.simplify = parseNumber(option, key, value, 1e-6, 1.0);
  } else {
    throw SweepError(option, "unknown key '" + key + "' (one of " + sweepKeys() + ", or surfels)");
  }
}

// "KEY=VALUE" split at its '=', or a ValidationError quoting `whole`.
std::pair<std::string, std::string> keyAndValue(const std::string& option, const std::string& text,
                                                const std::string& whole) {
  const std::size_t equals = text.find('=');
  if (equals == std::string::npos || equals == 0 || equals + 1 == text.size())
    throw SweepError(option, "expected KEY=V1,V2,…, KEY=V+KEY=V, surfels or exact, got '" + whole + "'");
  return {text.substr(0, equals), text.substr(equals + 1)};
}

EvalSetting baselineSettingNamed(const std::string& name, const LodOptions& baseline) {
  return EvalSetting{
      .name = name, .mode = RenderMode::Surfels, .samples = 1, .lod = baseline, .ordering = {}, .simplify = {}};
}

// "KEY=V+KEY=V…": one setting with every change at once.
EvalSetting combinedSetting(const std::string& option, const std::string& text, const LodOptions& baseline) {
  EvalSetting setting = baselineSettingNamed(text, baseline);
  std::istringstream parts(text);
  for (std::string part; std::getline(parts, part, '+');) {
    const auto [key, value] = keyAndValue(option, part, text);
    if (value.find(',') != std::string::npos)
      throw SweepError(option, "a combined setting takes one value per key, got '" + text + "'");
    apply(option, key, value, setting);
  }
  if (text.back() == '+') throw SweepError(option, "an empty part in '" + text + "'");
  return setting;
}

}  // namespace

bool EvalSetting::drawsLike(const EvalSetting& o) const {
  if (mode != o.mode || samples != o.samples) return false;
  return isPeer() || (lod == o.lod && ordering == o.ordering && simplify == o.simplify);
}

std::string sweepKeys() {
  return "embree, exact, overdraw, threshold, primitives, ms, exhausted, rays, rays-preference, rays-near-share, "
         "point, splat, cull, "
         "gain, band, rule, geometry, ordering, simplify";
}

std::vector<EvalSetting> parseSweep(const std::string& text, const LodOptions& baseline, const std::string& option) {
  if (text == "surfels") return {baselineSettingNamed("surfels", baseline)};
  if (text == "exact") return parseSweep("exact=1", baseline, option);
  if (text.find('+') != std::string::npos) return {combinedSetting(option, text, baseline)};
  const auto [key, list] = keyAndValue(option, text, text);
  std::vector<EvalSetting> settings;
  std::istringstream values(list);
  for (std::string value; std::getline(values, value, ',');) {
    EvalSetting setting = baselineSettingNamed(key + "=" + value, baseline);
    apply(option, key, value, setting);
    if (setting.isPeer()) setting.name = key + "=" + std::to_string(setting.samples);
    settings.push_back(std::move(setting));
  }
  if (settings.empty() || text.back() == ',') throw SweepError(option, "an empty value in '" + text + "'");
  return settings;
}

std::vector<std::string> defaultPeers() { return {"embree=1,4,16", "exact=1"}; }

std::vector<std::string> defaultSweep(SurfelOrdering fileOrdering) {
  std::vector<std::string> sweeps = {"overdraw=4,8,32", "threshold=64,256", "splat=nearest"};
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

std::vector<EvalSetting> evalSettings(const std::vector<std::string>& peers, const std::vector<std::string>& sweeps,
                                      const LodOptions& baseline) {
  std::vector<EvalSetting> settings;
  const auto add = [&](const std::string& text, const std::string& option) {
    for (EvalSetting& setting : parseSweep(text, baseline, option)) {
      if (option == "--peers" && !setting.isPeer())
        throw SweepError("--peers", "takes embree=N,… and exact=N,… only, got '" + text + "'");
      const bool seen = std::any_of(settings.begin(), settings.end(), [&](const EvalSetting& s) {
        return s.drawsLike(setting) || s.name == setting.name;
      });
      if (!seen) settings.push_back(std::move(setting));
    }
  };
  for (const std::string& peer : peers) add(peer, "--peers");
  add("surfels", "--sweep");
  for (const std::string& sweep : sweeps) add(sweep, "--sweep");
  return settings;
}

std::size_t baselineSetting(const std::vector<EvalSetting>& settings) {
  for (std::size_t i = 0; i < settings.size(); ++i)
    if (settings[i].name == "surfels") return i;
  throw std::logic_error("evalSettings always adds the baseline setting \"surfels\"");
}

}  // namespace pbs
