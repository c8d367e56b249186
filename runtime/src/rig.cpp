#include "facerig/runtime/ascii_case.h"
#include "facerig/runtime/rig.h"

#include <algorithm>
#include <cctype>

namespace facerig {

double MetresPerUnit(Units units) {
  switch (units) {
    case Units::kMillimetres: return 0.001;
    case Units::kCentimetres: return 0.01;
    case Units::kMetres:
    case Units::kUnknown: return 1.0;
  }
  return 1.0;
}

const char* ToString(Units units) {
  switch (units) {
    case Units::kMillimetres: return "mm";
    case Units::kCentimetres: return "cm";
    case Units::kMetres: return "m";
    case Units::kUnknown: return "unknown";
  }
  return "unknown";
}

const char* ToString(UpAxis up) { return up == UpAxis::kZ ? "+Z" : "+Y"; }

std::optional<Units> ParseUnits(std::string_view text) {
  const std::string lower = LowerAscii(text);
  if (lower == "mm" || lower == "millimetres" || lower == "millimeters") return Units::kMillimetres;
  if (lower == "cm" || lower == "centimetres" || lower == "centimeters") return Units::kCentimetres;
  if (lower == "m" || lower == "metres" || lower == "meters") return Units::kMetres;
  if (lower == "unknown") return Units::kUnknown;
  return std::nullopt;
}

BlendShapeView Rig::shape(std::size_t index) const {
  const ShapeRange& range = shape_ranges_[index];
  BlendShapeView view;
  view.name = shape_names_[index];
  view.vertex_indices = std::span(shape_vertex_indices_).subspan(range.offset, range.count);
  view.position_deltas = std::span(shape_position_deltas_).subspan(range.offset, range.count);
  if (has_normal_deltas_) {
    view.normal_deltas = std::span(shape_normal_deltas_).subspan(range.offset, range.count);
  }
  return view;
}

std::optional<std::size_t> Rig::FindShape(std::string_view name) const {
  for (std::size_t i = 0; i < shape_names_.size(); ++i) {
    if (shape_names_[i] == name) return i;
  }
  return std::nullopt;
}

const Part* Rig::FindPart(std::string_view name) const {
  for (const Part& part : parts_) {
    if (part.name == name) return &part;
  }
  return nullptr;
}

}  // namespace facerig
