#include "facerig/offline/default_head/default_head.h"

#include <algorithm>
#include <cstddef>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <catch2/catch.hpp>
#include <glm/geometric.hpp>

#include "facerig/offline/rigging/standard_shapes.h"
#include "support/default_head_poses.h"
#include "facerig/runtime/files/frig.h"
#include "facerig/runtime/io/gltf.h"

namespace {

// Where the build generates the head (`facerig default-head`).
std::filesystem::path DataDir() { return std::filesystem::path(FACERIG_DEFAULT_HEAD).parent_path(); }

std::vector<std::byte> ReadBytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::vector<char> chars((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::vector<std::byte> bytes(chars.size());
  std::transform(chars.begin(), chars.end(), bytes.begin(), [](char c) { return static_cast<std::byte>(c); });
  return bytes;
}

float MaxGap(const std::vector<glm::vec3>& positions, const std::vector<std::uint32_t>& upper,
             const std::vector<std::uint32_t>& lower) {
  REQUIRE(upper.size() == lower.size());
  float gap = 0.0f;
  for (std::size_t i = 0; i < upper.size(); ++i) {
    gap = std::max(gap, glm::length(positions[upper[i]] - positions[lower[i]]));
  }
  return gap;
}

const std::vector<std::string> kRequiredShapes = {
    "jawOpen", "mouthClose", "mouthFunnel", "mouthPucker", "mouthRollLower", "mouthRollUpper",
    "mouthPress_L", "mouthPress_R", "mouthStretch_L", "mouthStretch_R", "mouthSmile_L", "mouthSmile_R",
    "mouthFrown_L", "mouthFrown_R", "mouthLowerDown_L", "mouthLowerDown_R", "mouthUpperUp_L",
    "mouthUpperUp_R", "eyeBlink_L", "eyeBlink_R", "eyeWide_L", "eyeWide_R", "eyeSquint_L", "eyeSquint_R",
    "browInnerUp_L", "browInnerUp_R", "browDown_L", "browDown_R", "browOuterUp_L", "browOuterUp_R",
    "cheekPuff_L", "cheekPuff_R", "noseSneer_L", "noseSneer_R", "eyeLookUp_L", "eyeLookUp_R",
    "eyeLookDown_L", "eyeLookDown_R", "eyeLookIn_L", "eyeLookIn_R", "eyeLookOut_L", "eyeLookOut_R",
    "jawForward", "jawLeft", "jawRight", "mouthLeft", "mouthRight", "mouthShrugLower", "mouthShrugUpper",
    "tongueOut", "mouthDimple_L", "mouthDimple_R", "cheekSquint_L", "cheekSquint_R"};

}  // namespace

TEST_CASE("Default head: structure, units and parts", "[default_head]") {
  facerig::DefaultHeadFeatures features;
  const facerig::Rig& rig = facerig::test::DefaultHead(&features);
  CHECK(rig.units() == facerig::Units::kCentimetres);
  CHECK(rig.up_axis() == facerig::UpAxis::kY);
  // 2 linear + 2 Loop subdivisions: 4^4 dense triangles per control triangle.
  CHECK(rig.FindPart("skin")->triangle_count == 256u * features.control_triangle_count);
  CHECK(rig.vertex_count() >= 5000);
  CHECK(rig.vertex_count() <= 17000);
  for (const char* part : {"skin", "eye_white_L", "eye_white_R", "iris_L", "iris_R", "pupil_L", "pupil_R",
                           "teeth_upper", "teeth_lower", "mouth_inner", "tongue"}) {
    INFO(part);
    const facerig::Part* p = rig.FindPart(part);
    REQUIRE(p);
    CHECK(p->triangle_count > 0);
  }
  // A human-sized head: about 23 cm from chin to crown, eyes 6 to 7 cm apart.
  const float eye_distance = glm::length(features.eye_centres[0] - features.eye_centres[1]);
  CHECK(eye_distance > 5.8f);
  CHECK(eye_distance < 7.0f);
  CHECK(features.eye_centres[0].x > 0.0f);  // the character's left is +X
}

TEST_CASE("Default head: the files the build generated are the library's head", "[default_head]") {
  // As `facerig default-head` writes it: with its defaults, Apple's ARKit
  // names and the 15 Oculus visemes baked (standard_shapes.h).
  const facerig::Rig rig = facerig::StandardizeShapes(facerig::test::DefaultHead()).rig;
  const std::vector<std::byte> generated = ReadBytes(DataDir() / "default_head.frig");
  REQUIRE_FALSE(generated.empty());
  // Byte-identical: the generator is deterministic (`facerig default-head
  // build/data`, run by the build; previews with --preview).
  const std::vector<std::byte> regenerated = facerig::SerializeFrig(rig);
  CHECK(regenerated.size() == generated.size());
  const bool identical = regenerated == generated;
  CHECK(identical);

  const facerig::Rig glb = facerig::ReadGltf(DataDir() / "default_head.glb");
  REQUIRE(glb.vertex_count() == rig.vertex_count());
  REQUIRE(glb.shape_count() == rig.shape_count());
  CHECK(std::equal(glb.triangles().begin(), glb.triangles().end(), rig.triangles().begin()));
  CHECK(std::equal(glb.positions().begin(), glb.positions().end(), rig.positions().begin()));
  for (std::size_t s = 0; s < rig.shape_count(); ++s) {
    const facerig::BlendShapeView a = rig.shape(s), b = glb.shape(s);
    CHECK(a.name == b.name);
    CHECK(std::equal(a.vertex_indices.begin(), a.vertex_indices.end(), b.vertex_indices.begin(),
                     b.vertex_indices.end()));
    CHECK(std::equal(a.position_deltas.begin(), a.position_deltas.end(), b.position_deltas.begin(),
                     b.position_deltas.end()));
  }
}

TEST_CASE("Default head: every shape moves something, and only where it should", "[default_head]") {
  facerig::DefaultHeadFeatures features;
  const facerig::Rig& rig = facerig::test::DefaultHead(&features);
  const float nose_y = rig.positions()[features.nose_tip].y;
  const float eye_y = features.eye_centres[0].y;
  const float mouth_y = rig.positions()[features.mouth_corners[0]].y;
  for (const std::string& name : kRequiredShapes) {
    INFO(name);
    const auto index = rig.FindShape(name);
    REQUIRE(index);
    const facerig::BlendShapeView shape = rig.shape(*index);
    REQUIRE_FALSE(shape.vertex_indices.empty());
    float largest = 0.0f;
    for (const glm::vec3& d : shape.position_deltas) largest = std::max(largest, glm::length(d));
    CHECK(largest > 0.1f);  // cm: visible
    CHECK(largest < 4.0f);
    const bool left = name.ends_with("_L"), right = name.ends_with("_R");
    const bool upper_face = name.starts_with("eye") || name.starts_with("brow");
    const bool mouth = name.starts_with("mouth") || name.starts_with("jaw");
    float largest_other_side = 0.0f;
    for (std::size_t i = 0; i < shape.vertex_indices.size(); ++i) {
      const float length = glm::length(shape.position_deltas[i]);
      // The coarse control face spreads a displacement over its neighbouring
      // control triangles; a few percent of the peak there is invisible.
      if (length < 0.03f * largest) continue;
      const glm::vec3 p = rig.positions()[shape.vertex_indices[i]];
      // Eyes and brows stay above the nose tip; a squint raises the cheek too.
      if (upper_face) REQUIRE(p.y > (name.starts_with("eyeSquint") ? mouth_y : nose_y));
      if (mouth) REQUIRE(p.y < eye_y + 0.5f); // mouth and jaw stay below the upper lids
      if (!left && !right) continue;
      const float sided_x = left ? p.x : -p.x;  // > 0 on the shape's own side
      if (!mouth) REQUIRE(sided_x > -0.3f);     // an eye/brow/cheek/nose _L shape leaves the right alone
      if (sided_x < -1.0f) largest_other_side = std::max(largest_other_side, length);
    }
    // Sided mouth shapes move the middle of the lips a little, the far side not at all.
    CHECK(largest_other_side <= 0.25f * largest);
  }
}

TEST_CASE("Default head: a blink closes the lids over the eyeball", "[default_head]") {
  facerig::DefaultHeadFeatures features;
  const facerig::Rig& rig = facerig::test::DefaultHead(&features);
  for (int side = 0; side < 2; ++side) {
    INFO("side " << side);
    const auto s = static_cast<std::size_t>(side);
    const std::vector<glm::vec3> open(rig.positions().begin(), rig.positions().end());
    const float open_gap = MaxGap(open, features.upper_lid[s], features.lower_lid[s]);
    CHECK(open_gap > 0.7f);  // cm: the eye is open at rest
    const std::vector<glm::vec3> closed = facerig::test::Posed(rig, {{side == 0 ? "eyeBlink_L" : "eyeBlink_R", 1.0f}});
    // The margins meet: every upper margin vertex on its lower partner.
    CHECK(MaxGap(closed, features.upper_lid[s], features.lower_lid[s]) < 0.01f);
    // No skin vertex enters the eyeball, at any weight along the way.
    for (const float w : {0.25f, 0.5f, 0.75f, 1.0f}) {
      const std::vector<glm::vec3> posed = facerig::test::Posed(rig, {{side == 0 ? "eyeBlink_L" : "eyeBlink_R", w}});
      float nearest = 1e9f;
      for (std::uint32_t v = 0; v < features.skin_vertex_count; ++v) {
        nearest = std::min(nearest, glm::length(posed[v] - features.eye_centres[s]));
      }
      INFO("weight " << w << ": nearest skin vertex " << nearest << " cm from the eye centre");
      CHECK(nearest > features.eyeball_radius + 0.02f);
    }
  }
}

TEST_CASE("Default head: lips closed at rest, and closed by mouthClose with the jaw a little open",
          "[default_head]") {
  facerig::DefaultHeadFeatures features;
  const facerig::Rig& rig = facerig::test::DefaultHead(&features);
  const std::vector<glm::vec3> rest(rig.positions().begin(), rig.positions().end());
  CHECK(MaxGap(rest, features.upper_lip, features.lower_lip) < 0.15f);
  const std::vector<glm::vec3> open = facerig::test::Posed(rig, {{"jawOpen", 0.2f}});
  CHECK(MaxGap(open, features.upper_lip, features.lower_lip) > 0.5f);
  const std::vector<glm::vec3> closed = facerig::test::Posed(rig, {{"jawOpen", 0.2f}, {"mouthClose", 0.2f}});
  CHECK(MaxGap(closed, features.upper_lip, features.lower_lip) < 0.15f);
  // The middle of the lips (the midline vertex pair) meets to well under a millimetre.
  const std::size_t mid = features.upper_lip.size() / 2;
  CHECK(glm::length(closed[features.upper_lip[mid]] - closed[features.lower_lip[mid]]) < 0.05f);
}

TEST_CASE("Default head: jawOpen rotates the jaw about a hinge", "[default_head]") {
  const facerig::Rig& rig = facerig::test::DefaultHead();
  const std::vector<glm::vec3> open = facerig::test::Posed(rig, {{"jawOpen", 1.0f}});
  // Lower teeth move rigidly: distances within the row are kept (a rotation,
  // not a stretch), and they move down.
  const facerig::Part* teeth = rig.FindPart("teeth_lower");
  REQUIRE(teeth);
  const std::uint32_t a = teeth->first_vertex, b = teeth->first_vertex + teeth->vertex_count - 1;
  CHECK(glm::length(open[a] - open[b]) == Approx(glm::length(rig.positions()[a] - rig.positions()[b])).epsilon(1e-4));
  CHECK(open[a].y < rig.positions()[a].y - 1.0f);
  // Upper teeth do not move.
  const facerig::Part* upper = rig.FindPart("teeth_upper");
  CHECK(open[upper->first_vertex] == rig.positions()[upper->first_vertex]);
}

TEST_CASE("Default head: in 'oh' the lips hide the lower teeth and most of the upper ones", "[default_head]") {
  facerig::DefaultHeadFeatures features;
  const facerig::Rig& rig = facerig::test::DefaultHead(&features);
  const std::vector<glm::vec3> oh = facerig::test::Posed(rig, {{"jawOpen", 0.35f}, {"mouthFunnel", 0.9f}});
  const std::size_t mid = features.upper_lip.size() / 2;
  const float upper_lip = oh[features.upper_lip[mid]].y, lower_lip = oh[features.lower_lip[mid]].y;
  // The front teeth (near the midline): the upper row's lowest point, the lower row's highest.
  auto extreme = [&](const char* name, bool highest) {
    const facerig::Part* part = rig.FindPart(name);
    REQUIRE(part);
    float y = highest ? -1e9f : 1e9f;
    for (std::uint32_t v = part->first_vertex; v < part->first_vertex + part->vertex_count; ++v) {
      if (std::abs(oh[v].x) > 0.5f) continue;
      y = highest ? std::max(y, oh[v].y) : std::min(y, oh[v].y);
    }
    return y;
  };
  const float upper_edge = extreme("teeth_upper", false), lower_edge = extreme("teeth_lower", true);
  INFO("lips " << upper_lip << " / " << lower_lip << ", teeth edges " << upper_edge << " / " << lower_edge);
  REQUIRE(upper_lip - lower_lip > 0.8f);  // open
  CHECK(lower_edge < lower_lip);  // the lower row behind the lower lip
  CHECK(upper_lip - upper_edge < 0.35f * (upper_lip - lower_lip));  // a strip of the upper row, not a snarl
  CHECK(upper_lip - upper_edge > 0.0f);  // its edge peeks out
}

TEST_CASE("Default head: proportions of a person: a short neck, lips sealed at rest, a round 'oh'",
          "[default_head]") {
  facerig::DefaultHeadFeatures features;
  const facerig::Rig& rig = facerig::test::DefaultHead(&features);
  const std::vector<glm::vec3> rest(rig.positions().begin(), rig.positions().end());
  // The neck ends a neck's length below the chin, not a column below it.
  float chin = 1e9f, lowest = 1e9f;
  for (std::uint32_t v = 0; v < features.skin_vertex_count; ++v) {
    lowest = std::min(lowest, rest[v].y);
    if (std::abs(rest[v].x) < 0.5f && rest[v].z > 5.0f) chin = std::min(chin, rest[v].y);
  }
  INFO("chin " << chin << " cm, bottom of the neck " << lowest << " cm");
  CHECK(chin - lowest > 3.5f);
  CHECK(chin - lowest < 7.0f);
  // At rest the lips meet along the whole margin: nothing shows between them.
  CHECK(MaxGap(rest, features.upper_lip, features.lower_lip) < 0.01f);
  // "oh": the opening is round, not a diamond. Half way to the corners an
  // ellipse is sqrt(3)/2 of its middle height; a diamond half.
  const std::vector<glm::vec3> oh = facerig::test::Posed(rig, {{"mouthFunnel", 1.0f}});
  const std::size_t n = features.upper_lip.size(), mid = n / 2;
  const float middle = oh[features.upper_lip[mid]].y - oh[features.lower_lip[mid]].y;
  const float half_width = 0.5f * (oh[features.mouth_corners[0]].x - oh[features.mouth_corners[1]].x);
  CHECK(middle > 0.35f * half_width);  // open, not a slit
  for (std::size_t i = 0; i < n; ++i) {
    const float x = oh[features.upper_lip[i]].x;
    if (std::abs(std::abs(x) - 0.5f * half_width) > 0.1f * half_width) continue;
    const float height = oh[features.upper_lip[i]].y - oh[features.lower_lip[i]].y;
    INFO("margin pair " << i << " at x " << x << ": " << height << " cm open, " << middle << " in the middle");
    CHECK(height > 0.75f * middle);
  }
}

TEST_CASE("Default head: tongueOut brings the tongue past the lips", "[default_head]") {
  facerig::DefaultHeadFeatures features;
  const facerig::Rig& rig = facerig::test::DefaultHead(&features);
  const facerig::Part* tongue = rig.FindPart("tongue");
  REQUIRE(tongue);
  const auto tongue_tip_z = [&](const std::vector<glm::vec3>& positions) {
    float z = -1e9f;
    for (std::uint32_t v = tongue->first_vertex; v < tongue->first_vertex + tongue->vertex_count; ++v) {
      z = std::max(z, positions[v].z);
    }
    return z;
  };
  float lips_z = -1e9f;
  for (std::uint32_t v : features.lower_lip) lips_z = std::max(lips_z, rig.positions()[v].z);
  const std::vector<glm::vec3> rest(rig.positions().begin(), rig.positions().end());
  CHECK(tongue_tip_z(rest) < lips_z);  // inside the mouth at rest
  CHECK(tongue_tip_z(facerig::test::Posed(rig, {{"tongueOut", 1.0f}})) > lips_z + 0.3f);
}
