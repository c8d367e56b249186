#include "facerig/offline/rigging/standard_shapes.h"

#include <algorithm>
#include <stdexcept>
#include <unordered_set>
#include <utility>

#include "facerig/runtime/rig_builder.h"
#include "facerig/runtime/shape_names.h"
#include "facerig/runtime/speech/viseme_mapping.h"

namespace facerig {
namespace {

// A weighted sum of sparse shapes over the rig's vertices.
class ShapeSum {
 public:
  ShapeSum(std::size_t vertex_count, bool normals)
      : positions_(vertex_count, glm::vec3(0.0f)), normals_(normals ? vertex_count : 0, glm::vec3(0.0f)),
        touched_(vertex_count, false) {}

  void Add(const BlendShapeView& shape, float weight) {
    for (std::size_t i = 0; i < shape.vertex_indices.size(); ++i) {
      const std::uint32_t v = shape.vertex_indices[i];
      positions_[v] += weight * shape.position_deltas[i];
      if (!normals_.empty() && !shape.normal_deltas.empty()) normals_[v] += weight * shape.normal_deltas[i];
      touched_[v] = true;
    }
  }

  RawBlendShape Take(std::string name) const {
    RawBlendShape shape;
    shape.name = std::move(name);
    for (std::uint32_t v = 0; v < touched_.size(); ++v) {
      if (!touched_[v]) continue;
      shape.vertex_indices.push_back(v);
      shape.position_deltas.push_back(positions_[v]);
      if (!normals_.empty()) shape.normal_deltas.push_back(normals_[v]);
    }
    return shape;
  }

 private:
  std::vector<glm::vec3> positions_, normals_;
  std::vector<bool> touched_;
};

RawBlendShape CopyShape(const BlendShapeView& view, std::string name) {
  return {std::move(name),
          {view.vertex_indices.begin(), view.vertex_indices.end()},
          {view.position_deltas.begin(), view.position_deltas.end()},
          {view.normal_deltas.begin(), view.normal_deltas.end()}};
}

bool SameCanonical(const CanonicalShapeName& a, const CanonicalShapeName& b) {
  return a.base == b.base && a.side == b.side;
}

// The ARKit name (index into kArkitShapeNames) a shape's name spells, if any.
std::optional<std::size_t> ArkitIndexOf(const CanonicalShapeName& name) {
  for (std::size_t a = 0; a < kArkitShapeCount; ++a) {
    if (SameCanonical(CanonicalShapeNameOf(kArkitShapeNames[a]), name)) return a;
  }
  return std::nullopt;
}

// One output shape: where it comes from and the name it should get.
struct PlannedShape {
  std::vector<std::size_t> sources;  // one shape, or a left and a right half to add
  std::string original, wanted;
};

// The unsided ARKit names the rig has only as a left and a right half:
// ARKit index -> {left shape, right shape}.
std::vector<std::pair<std::size_t, std::pair<std::size_t, std::size_t>>> HalvesToMerge(
    const std::vector<CanonicalShapeName>& names, const std::vector<bool>& is_viseme) {
  std::vector<std::pair<std::size_t, std::pair<std::size_t, std::size_t>>> merges;
  for (std::size_t a = 0; a < kArkitShapeCount; ++a) {
    const CanonicalShapeName arkit = CanonicalShapeNameOf(kArkitShapeNames[a]);
    if (arkit.side != 0) continue;
    std::optional<std::size_t> whole, left, right;
    for (std::size_t s = 0; s < names.size(); ++s) {
      if (is_viseme[s] || names[s].base != arkit.base) continue;
      std::optional<std::size_t>& slot = names[s].side == 'l' ? left : names[s].side == 'r' ? right : whole;
      if (!slot) slot = s;
    }
    if (!whole && left && right) merges.push_back({a, {*left, *right}});
  }
  return merges;
}

// The rig's shapes in order, renamed (and halves merged) as `naming` says;
// viseme targets are left out when `drop_visemes`, else renamed to the Oculus
// spelling when `oculus_names`.
std::vector<PlannedShape> PlanShapes(const Rig& rig, ShapeNaming naming, bool drop_visemes, bool oculus_names,
                                     StandardShapesReport& report) {
  std::vector<CanonicalShapeName> names;
  std::vector<bool> is_viseme;
  for (std::size_t s = 0; s < rig.shape_count(); ++s) {
    names.push_back(CanonicalShapeNameOf(rig.shape_name(s)));
    is_viseme.push_back(VisemeOfTargetName(rig.shape_name(s)).has_value());
  }
  std::vector<std::optional<std::size_t>> merged_into(rig.shape_count());  // ARKit index
  std::vector<bool> right_half(rig.shape_count(), false);
  if (naming == ShapeNaming::kArkit) {
    for (const auto& [a, halves] : HalvesToMerge(names, is_viseme)) {
      merged_into[halves.first] = a;
      right_half[halves.second] = true;
      report.merged.emplace_back(kArkitShapeNames[a]);
    }
  }
  std::vector<PlannedShape> planned;
  for (std::size_t s = 0; s < rig.shape_count(); ++s) {
    const std::string original(rig.shape_name(s));
    if (right_half[s] || (is_viseme[s] && drop_visemes)) continue;
    if (merged_into[s]) {
      const std::size_t a = *merged_into[s];
      std::size_t right = s;
      for (std::size_t r = 0; r < rig.shape_count(); ++r) {
        if (right_half[r] && names[r].base == names[s].base) right = r;
      }
      planned.push_back({{s, right}, original, std::string(kArkitShapeNames[a])});
      continue;
    }
    std::string wanted = original;
    if (is_viseme[s]) {
      if (oculus_names) wanted = OculusTargetName(*VisemeOfTargetName(original));
    } else if (naming != ShapeNaming::kKeep) {
      if (const std::optional<std::size_t> a = ArkitIndexOf(names[s])) {
        wanted = naming == ShapeNaming::kArkit ? std::string(kArkitShapeNames[*a]) : IctShapeName(kArkitShapeNames[*a]);
      }
    }
    planned.push_back({{s}, original, std::move(wanted)});
  }
  return planned;
}

// Gives each planned shape its wanted name unless another shape already has
// it (a rig with both eyeBlink_L and eyeBlinkLeft): a shape spelled as
// wanted keeps it, the other keeps its own name. Returns the final names.
std::vector<std::string> UniqueNames(const std::vector<PlannedShape>& planned, StandardShapesReport& report) {
  std::unordered_set<std::string> taken;
  for (const PlannedShape& p : planned) {
    if (p.sources.size() == 1 && p.wanted == p.original) taken.insert(p.wanted);
  }
  std::vector<std::string> final_names;
  for (const PlannedShape& p : planned) {
    if (p.sources.size() == 1 && p.wanted == p.original) {
      final_names.push_back(p.wanted);
      continue;
    }
    std::string name = p.wanted;
    if (taken.contains(name)) {
      report.warnings.push_back("shape " + p.original + " keeps its name: " + p.wanted + " is already taken");
      name = p.original;
      while (taken.contains(name)) name += "_2";
    }
    if (name != p.original) ++report.renamed;
    taken.insert(name);
    final_names.push_back(std::move(name));
  }
  return final_names;
}

// viseme_sil ... viseme_U, each the mapping's blend of the rig's shapes at
// full viseme weight (jaw and lip intensities 1).
std::vector<RawBlendShape> BakeVisemes(const Rig& rig, const VisemeMapping& mapping) {
  std::vector<RawBlendShape> baked;
  for (std::size_t v = 0; v < kVisemeCount; ++v) {
    const auto viseme = static_cast<Viseme>(v);
    ShapeSum sum(rig.vertex_count(), rig.has_normal_deltas());
    for (const ShapeContribution& c : mapping.contributions(viseme)) sum.Add(rig.shape(c.shape), c.weight);
    baked.push_back(sum.Take(std::string(OculusTargetName(viseme))));
  }
  return baked;
}

}  // namespace

std::optional<ShapeNaming> ParseShapeNaming(std::string_view text) {
  if (text == "arkit") return ShapeNaming::kArkit;
  if (text == "ict") return ShapeNaming::kIct;
  if (text == "keep") return ShapeNaming::kKeep;
  return std::nullopt;
}

std::optional<VisemeTargets> ParseVisemeTargets(std::string_view text) {
  if (text == "oculus") return VisemeTargets::kOculus;
  if (text == "none") return VisemeTargets::kNone;
  return std::nullopt;
}

const char* ToString(ShapeNaming naming) {
  switch (naming) {
    case ShapeNaming::kArkit: return "arkit";
    case ShapeNaming::kIct: return "ict";
    case ShapeNaming::kKeep: return "keep";
  }
  return "unknown";
}

const char* ToString(VisemeTargets visemes) { return visemes == VisemeTargets::kOculus ? "oculus" : "none"; }

StandardShapesResult StandardizeShapes(const Rig& rig, const StandardShapesOptions& options) {
  StandardShapesReport report;
  std::optional<VisemeMapping> bake_from;
  if (options.visemes == VisemeTargets::kOculus) {
    VisemeMappingResult arkit = BuildVisemeMapping(rig, {VisemeMappingStyle::kArkit, nullptr});
    if (!arkit.mapping.empty()) {
      for (std::string& warning : arkit.warnings) report.warnings.push_back("visemes: " + std::move(warning));
      bake_from = std::move(arkit.mapping);
    }
  }
  const std::vector<PlannedShape> planned = PlanShapes(rig, options.names, bake_from.has_value(),
                                                       options.visemes == VisemeTargets::kOculus, report);
  const std::vector<std::string> final_names = UniqueNames(planned, report);

  RawRig raw = RigBuilder::ToRaw(rig);
  raw.shapes.clear();
  for (std::size_t i = 0; i < planned.size(); ++i) {
    const PlannedShape& p = planned[i];
    if (p.sources.size() == 1) {
      raw.shapes.push_back(CopyShape(rig.shape(p.sources[0]), final_names[i]));
      continue;
    }
    ShapeSum halves(rig.vertex_count(), rig.has_normal_deltas());
    for (std::size_t s : p.sources) halves.Add(rig.shape(s), 1.0f);
    raw.shapes.push_back(halves.Take(final_names[i]));
  }
  if (bake_from) {
    for (RawBlendShape& shape : BakeVisemes(rig, *bake_from)) raw.shapes.push_back(std::move(shape));
    report.visemes_baked = kVisemeCount;
  }
  std::string problem;
  std::optional<Rig> result = RigBuilder::Build(std::move(raw), &problem);
  if (!result) throw std::runtime_error("naming the rig's shapes made an invalid rig: " + problem);

  // Under kArkit only Apple's exact spelling counts as present.
  const ShapeNameReport names = MatchShapeNames(*result);
  for (const ArkitShapeMatch& match : names.matched) {
    if (options.names != ShapeNaming::kArkit || match.kind == ShapeMatchKind::kExact) {
      ++report.arkit_present;
    } else {
      report.arkit_missing.emplace_back(match.arkit_name);
    }
  }
  for (std::string_view missing : names.missing) report.arkit_missing.emplace_back(missing);
  report.viseme_targets = names.viseme_targets.size();
  return {std::move(*result), std::move(report)};
}

Rig WithoutBakedVisemes(const Rig& rig, std::size_t* removed) {
  RawRig raw = RigBuilder::ToRaw(rig);
  std::size_t dropped = 0;
  if (!BuildVisemeMapping(rig, {VisemeMappingStyle::kArkit, nullptr}).mapping.empty()) {
    const auto before = raw.shapes.size();
    std::erase_if(raw.shapes, [](const RawBlendShape& shape) { return VisemeOfTargetName(shape.name).has_value(); });
    dropped = before - raw.shapes.size();
  }
  if (removed) *removed = dropped;
  std::string problem;
  std::optional<Rig> result = RigBuilder::Build(std::move(raw), &problem);
  if (!result) throw std::runtime_error("removing the viseme targets made an invalid rig: " + problem);
  return std::move(*result);
}

}  // namespace facerig
