// `facerig build`, run in-process: outputs on the target's own topology (GLB
// accepted by the Khronos validator, .frig, an OBJ per shape), the report,
// and clear errors with nothing written on bad input.
#include "build_command.h"
#include "cli/app.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <catch2/catch.hpp>
#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include "facerig/offline/landmarks/landmarks.h"
#include "facerig/offline/registration/nonrigid_icp.h"
#include "facerig/runtime/io/gltf.h"
#include "facerig/runtime/io/obj.h"
#include "facerig/runtime/io/rig_file.h"
#include "facerig/runtime/shape_names.h"
#include "support/command_runner.h"
#include "support/decimate.h"
#include "support/gltf_validator.h"
#include "support/ict_faces.h"
#include "support/skinned_gltf.h"
#include "support/test_meshes.h"

namespace facerig {
namespace {

namespace fs = std::filesystem;

void WriteTarget(const fs::path& path, const test::RegistrationTarget& target) {
  WriteObj(path, target.positions, {}, {}, target.triangles, {});
}

void WriteTrueLandmarks(const fs::path& path, const test::RegistrationTarget& target) {
  FaceLandmarks landmarks;
  for (std::uint32_t i = 0; i < kDlibLandmarkCount; ++i) {
    landmarks.points.push_back(target.true_landmarks[i]);
    landmarks.indices.push_back(i);
    landmarks.confidence.push_back(i < 17 ? 0.2f : 1.0f);
  }
  WriteLandmarksJson(path, landmarks);
}

using test::RunBuildCommand;

fs::path DefaultHead() { return FACERIG_DEFAULT_HEAD; }

// The rig's neutral as OBJ text with a UV per corner (a front projection) and
// two materials: "skin", and "lips" for the triangles below the nose, whose
// UVs are shifted by 0.5 so that the border between them is a UV seam. The
// materials interleave in the file (usemtl at each change).
std::string TexturedObj(const Rig& rig) {
  glm::vec3 lo = rig.positions()[0], hi = lo;
  for (const glm::vec3& p : rig.positions()) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  std::string text;
  for (const glm::vec3& p : rig.positions()) {
    text += "v " + std::to_string(p.x) + " " + std::to_string(p.y) + " " + std::to_string(p.z) + "\n";
  }
  std::string faces, current;
  std::size_t corner = 0;
  for (const Triangle& t : rig.triangles()) {
    const float centre_y = (rig.positions()[t[0]].y + rig.positions()[t[1]].y + rig.positions()[t[2]].y) / 3.0f;
    const bool lips = centre_y < lo.y + 0.3f * (hi.y - lo.y);
    const std::string material = lips ? "lips" : "skin";
    if (material != current) faces += "usemtl " + material + "\n";
    current = material;
    faces += "f";
    for (std::uint32_t v : t) {
      const glm::vec3 p = rig.positions()[v];
      const float u = (p.x - lo.x) / (hi.x - lo.x) * 0.5f + (lips ? 0.5f : 0.0f);
      text += "vt " + std::to_string(u) + " " + std::to_string((p.y - lo.y) / (hi.y - lo.y)) + "\n";
      faces += " " + std::to_string(v + 1) + "/" + std::to_string(++corner);
    }
    faces += "\n";
  }
  return text + faces;
}

}  // namespace

TEST_CASE("(shared data) facerig build: a re-meshed ICT face in millimetres gets the template's shapes on its own "
          "vertices, as GLB, .frig and OBJs",
          "[shared-data][cli]") {
  const fs::path folder = test::FreshOutputFolder("cli_build");
  test::RegistrationTargetOptions options;
  options.seed = 11;
  options.units_per_cm = 10.0;  // millimetres
  const test::RegistrationTarget target = test::MakeRegistrationTarget(options);
  WriteTarget(folder / "target.obj", target);
  WriteTrueLandmarks(folder / "landmarks.json", target);
  const fs::path ict_frig = folder / "ict.frig";
  SaveRig(ict_frig, test::IctRig());

  const test::CommandOutcome outcome =
      RunBuildCommand({"--template", ict_frig.string(), "--target", (folder / "target.obj").string(), "-o",
             (folder / "face.glb").string(), "--frig", (folder / "face.frig").string(), "--obj-dir",
             (folder / "shapes").string(), "--landmarks", (folder / "landmarks.json").string(), "--json",
             (folder / "report.json").string(), "--template-topology", (folder / "fit.frig").string()});
  INFO(outcome.error_output);
  REQUIRE(outcome.exit_code == 0);
  CHECK(outcome.error_output.find("register") != std::string::npos);  // the progress bar

  const Rig glb = LoadRig(folder / "face.glb");
  const Rig frig = LoadRig(folder / "face.frig");
  const Rig& ict = test::IctRig();
  REQUIRE(frig.vertex_count() == target.positions.size());
  CHECK(frig.units() == Units::kMillimetres);  // inferred from the registration's scale
  // Every ICT shape under its ARKit name (the default --names arkit), ICT's
  // left and right browInnerUp and cheekPuff as one each, tongueOut made from
  // ICT's tongue, and the 15 Oculus visemes (the default --visemes oculus).
  CHECK(frig.shape_count() == ict.shape_count() - 2 + 1 + 15);
  for (std::size_t s = 0; s < ict.shape_count(); ++s) {
    INFO(ict.shape_name(s));
    CHECK_FALSE(FindShapesByArkitName(frig, ict.shape_name(s)).empty());
  }
  for (const char* name : {"eyeBlinkLeft", "mouthSmileRight", "browInnerUp", "cheekPuff", "viseme_PP", "viseme_U"}) {
    CHECK(frig.FindShape(name).has_value());
  }
  const nlohmann::json names = nlohmann::json::parse(std::ifstream(folder / "report.json"))["result"]["shape_names"];
  // 52 of 52: ICT has no tongueOut, the build made one from its tongue.
  CHECK(names["arkit_present"] == 52);
  CHECK(names["arkit_missing"].empty());
  CHECK(names["visemes_baked"] == 15);
  const nlohmann::json build_report = nlohmann::json::parse(std::ifstream(folder / "report.json"));
  CHECK(build_report["result"]["tongue_out_synthesised_from"] == "gums_and_tongue");
  CHECK(outcome.error_output.find("made one from its part 'gums_and_tongue'") != std::string::npos);
  for (const nlohmann::json& warning : build_report["warnings"]) CHECK(warning["code"] != "missing_arkit_shapes");
  for (std::size_t v = 0; v < target.positions.size(); v += 97) {
    REQUIRE(frig.positions()[v].x == Approx(target.positions[v].x).margin(1e-3));
  }
  std::string difference;
  CHECK(test::RigsEqual(glb, frig, 1e-3f, &difference));
  INFO(difference);
  test::RequireValidatorAccepts(folder / "face.glb");

  // One OBJ per shape plus the neutral, each on the target's vertices, and
  // the MTL of the skin material the bare scan was given.
  CHECK(std::distance(fs::directory_iterator(folder / "shapes"), fs::directory_iterator{}) ==
        static_cast<std::ptrdiff_t>(frig.shape_count() + 2));
  CHECK(fs::exists(folder / "shapes" / "materials.mtl"));
  const Mesh neutral = ReadObj(folder / "shapes" / "neutral.obj");
  CHECK(neutral.positions.size() == target.positions.size());
  const Mesh jaw_open = ReadObj(folder / "shapes" / "jawOpen.obj");
  REQUIRE(jaw_open.positions.size() == target.positions.size());
  const BlendShapeView jaw = frig.shape(frig.FindShape("jawOpen").value());
  REQUIRE(!jaw.vertex_indices.empty());
  const std::uint32_t moved = jaw.vertex_indices[jaw.vertex_indices.size() / 2];
  const glm::vec3 expected = frig.positions()[moved] + jaw.position_deltas[jaw.vertex_indices.size() / 2];
  CHECK(jaw_open.positions[moved].y == Approx(expected.y).margin(1e-3));

  // The template's topology, in the template's frame (centimetres, near the ICT neutral).
  const Rig fit = LoadRig(folder / "fit.frig");
  REQUIRE(fit.vertex_count() == ict.vertex_count());
  CHECK(fit.units() == ict.units());
  CHECK(fit.shape_count() == frig.shape_count());
  double offset = 0.0;
  const std::uint32_t face = test::IctFaces().face_vertex_count();
  for (std::size_t v = 0; v < face; ++v) offset += glm::length(fit.positions()[v] - ict.positions()[v]);
  CHECK(offset / face < 1.0);  // cm: an identity, not another frame (mm, rotated, moved)

  std::ifstream report_file(folder / "report.json");
  const nlohmann::json report = nlohmann::json::parse(report_file);
  CHECK(report["command"] == "build");
  const nlohmann::json& result = report["result"];
  CHECK(result["target_vertices"] == target.positions.size());
  CHECK(result["units"] == "mm");
  CHECK(result["registration"]["residual_percent_of_diagonal"]["mean"].get<double>() < 0.1);
  CHECK(report["timings"]["total"].get<double>() > 0.0);
  CHECK(result["mapping"]["unmapped_vertices"] == 0);
  // Every stage of the build, in order, each with its time; they sum to the total.
  std::vector<std::string> stage_names;
  double stage_sum = 0.0;
  for (const nlohmann::json& stage : result["stages"]) {
    stage_names.push_back(stage["name"].get<std::string>());
    stage_sum += stage["seconds"].get<double>();
    CHECK(stage["seconds"].get<double>() >= 0.0);
  }
  CHECK(stage_names == std::vector<std::string>{"load", "prepare template", "landmarks", "register", "align margins",
                                                "to template frame", "transfer", "to target frame", "map", "write"});
  CHECK(stage_sum == Approx(report["timings"]["total"].get<double>()));
}

TEST_CASE("(shared data) facerig build: a skinned glTF target keeps its skin, nodes, material and animation",
          "[shared-data][cli]") {
  const fs::path folder = test::FreshOutputFolder("cli_build_skinned");
  test::RegistrationTargetOptions options;
  options.seed = 5;
  options.units_per_cm = 0.01;  // metres, as glTF
  options.target_vertex_count = 8000;
  const test::RegistrationTarget target = test::MakeRegistrationTarget(options);
  test::WriteSkinnedGltf(folder / "character.glb", {{target.positions, {}, {}, target.triangles}});
  WriteTrueLandmarks(folder / "landmarks.json", target);
  const fs::path ict_frig = folder / "ict.frig";
  SaveRig(ict_frig, test::IctRig());

  const test::CommandOutcome outcome =
      RunBuildCommand({"--template", ict_frig.string(), "--target", (folder / "character.glb").string(), "-o",
             (folder / "character_rig.glb").string(), "--landmarks", (folder / "landmarks.json").string()});
  INFO(outcome.error_output);
  REQUIRE(outcome.exit_code == 0);
  test::RequireValidatorAccepts(folder / "character_rig.glb");

  const test::GltfFile in = test::ReadGltfFile(folder / "character.glb");
  const test::GltfFile out = test::ReadGltfFile(folder / "character_rig.glb");
  for (const char* kept : {"nodes", "skins", "animations", "images"}) {
    INFO(kept);
    CHECK(in.document[kept] == out.document[kept]);
  }
  const nlohmann::json& attributes = out.document["meshes"][0]["primitives"][0]["attributes"];
  CHECK(attributes == in.document["meshes"][0]["primitives"][0]["attributes"]);
  for (const char* attribute : {"POSITION", "JOINTS_0", "WEIGHTS_0", "COLOR_0"}) {
    INFO(attribute);
    CHECK(test::AccessorBytes(in, attributes[attribute].get<int>()) ==
          test::AccessorBytes(out, attributes[attribute].get<int>()));
  }
  const int inverse_binds = in.document["skins"][0]["inverseBindMatrices"].get<int>();
  CHECK(test::AccessorBytes(in, inverse_binds) == test::AccessorBytes(out, inverse_binds));

  const Rig rig = LoadRig(folder / "character_rig.glb");
  CHECK(rig.vertex_count() == target.positions.size());
  CHECK(rig.shape_count() == test::IctRig().shape_count() - 2 + 1 + 15);  // ARKit names with tongueOut, Oculus visemes
  CHECK(rig.FindShape("jawOpen").has_value());
  CHECK(rig.FindShape("eyeBlinkLeft").has_value());
  CHECK(rig.FindShape("viseme_aa").has_value());
}

TEST_CASE("facerig build: --no-contacts and --no-eye-fit turn off contacts and eyes fitted to openings",
          "[cli]") {
  // The built-in head onto itself (about 6 s a build): its eyes are holes in
  // the skin, and its eyeBlink shapes close them (contacts).
  const fs::path folder = test::FreshOutputFolder("cli_build_switches");
  const std::string head = DefaultHead().string();
  const auto build_report = [&](const std::string& name, std::vector<std::string> switches) {
    std::vector<std::string> arguments{"--template", head, "--target", head, "-o",
                                       (folder / (name + ".frig")).string(), "--json",
                                       (folder / (name + ".json")).string()};
    arguments.insert(arguments.end(), switches.begin(), switches.end());
    const test::CommandOutcome outcome = RunBuildCommand(arguments);
    INFO(outcome.error_output);
    REQUIRE(outcome.exit_code == 0);
    std::ifstream file(folder / (name + ".json"));
    return nlohmann::json::parse(file)["result"];
  };
  const nlohmann::json defaults = build_report("defaults", {});
  CHECK(defaults["options"]["contacts"] == true);
  CHECK(defaults["options"]["eye_fit"] == true);
  CHECK(defaults["target_eyes_fitted"] == 2);
  // Its eyes are holes: every lid point on a margin, none doubtful, one build.
  CHECK(defaults["doubtful_lid_landmarks"]["points"].empty());
  CHECK(defaults["doubtful_lid_landmarks"]["kept"].is_null());
  CHECK(defaults["transfer_contacts"]["active"] == true);
  CHECK(defaults["transfer_contacts"]["pairs"].get<int>() > 0);
  // Its lid margins (the blinks' contacts) lie on its own eye rims already.
  CHECK(defaults["margin_alignment"]["vertices"].get<int>() > 0);
  CHECK(defaults["margin_alignment"]["mean_move"].get<double>() < 0.01);
  CHECK(defaults["mapping"]["rim_vertices"].get<int>() > 0);

  const nlohmann::json off = build_report("off", {"--no-contacts", "--no-eye-fit"});
  CHECK(off["options"]["contacts"] == false);
  CHECK(off["options"]["eye_fit"] == false);
  CHECK(off["target_eyes_fitted"] == 0);
  CHECK(off["transfer_contacts"]["active"] == false);
  CHECK(off["transfer_contacts"]["pairs"] == 0);
  CHECK(LoadRig(folder / "off.frig").shape_count() == LoadRig(folder / "defaults.frig").shape_count());
}

TEST_CASE("(shared data) facerig build: lid points detected on the eyeballs of a decimated ICT face are reported, "
          "and the build without them kept",
          "[shared-data][cli]") {
  // identity007 decimated: its sockets are closed, dlib puts the lower lids
  // on the eyeballs, and trusting them tears the blink (lid_choice.h).
  const fs::path folder = test::FreshOutputFolder("cli_build_lids");
  const Mesh face = ReadObj(test::IctDir() / "identity007.obj");
  const Mesh target = test::Decimate(face, 0.35).mesh;
  WriteObj(folder / "target.obj", target.positions, {}, {}, target.triangles, {});
  const test::CommandOutcome outcome =
      RunBuildCommand({"--template", test::IctDir().string(), "--target", (folder / "target.obj").string(), "-o",
                       (folder / "face.frig").string(), "--json", (folder / "report.json").string()});
  INFO(outcome.error_output);
  REQUIRE(outcome.exit_code == 0);
  CHECK(outcome.error_output.find("lid landmarks lay on the eye, not the skin") != std::string::npos);
  std::ifstream file(folder / "report.json");
  const nlohmann::json report = nlohmann::json::parse(file)["result"];
  const nlohmann::json& lids = report["doubtful_lid_landmarks"];
  CHECK(lids["points"] == std::vector<int>{40, 41, 46, 47});  // the lower lids
  CHECK(lids["kept"] == "dropped");
  CHECK(lids["blink_stretch_trusted"].get<double>() > 2.0 * lids["blink_stretch_dropped"].get<double>());
  const auto stages = report["stages"];
  CHECK(std::any_of(stages.begin(), stages.end(), [](const nlohmann::json& s) { return s["name"] == "lid choice"; }));
}

TEST_CASE("facerig build: an OBJ target's UVs and materials reach the GLB", "[cli]") {
  // The built-in head onto itself as a textured OBJ (about 6 s).
  const fs::path folder = test::FreshOutputFolder("cli_build_textured");
  const Rig head = LoadRig(DefaultHead());
  {
    std::ofstream obj(folder / "head.obj", std::ios::binary);
    obj << TexturedObj(head);
  }
  const test::CommandOutcome outcome = RunBuildCommand({"--template", DefaultHead().string(), "--target",
                                              (folder / "head.obj").string(), "-o", (folder / "head.glb").string(),
                                              "--frig", (folder / "head.frig").string()});
  INFO(outcome.error_output);
  REQUIRE(outcome.exit_code == 0);
  test::RequireValidatorAccepts(folder / "head.glb");

  const test::GltfFile file = test::ReadGltfFile(folder / "head.glb");
  REQUIRE(file.document["materials"].size() == 2);
  std::vector<std::string> material_names{file.document["materials"][0]["name"], file.document["materials"][1]["name"]};
  std::sort(material_names.begin(), material_names.end());
  CHECK(material_names == std::vector<std::string>{"lips", "skin"});
  for (const nlohmann::json& primitive : file.document["meshes"][0]["primitives"]) {
    CHECK(primitive["attributes"].contains("TEXCOORD_0"));
    CHECK(primitive.contains("material"));
  }

  // The OBJ's corners, grouped by part as the rig's triangles are: the same
  // UVs and materials, on copies of the seam vertices after the target's own.
  const Mesh expected = GroupedByPart(ReadObj(folder / "head.obj"));
  const Mesh written = ReadGltfMesh(folder / "head.glb");
  REQUIRE(written.triangle_count() == expected.triangle_count());
  CHECK(written.vertex_count() > expected.vertex_count());
  CHECK(written.triangle_materials == expected.triangle_materials);
  REQUIRE(written.corner_uvs.size() == expected.corner_uvs.size());
  std::size_t uv_mismatches = 0;
  for (std::size_t i = 0; i < expected.corner_uvs.size(); ++i) {
    if (glm::length(written.corner_uvs[i] - expected.corner_uvs[i]) > 1e-6f) ++uv_mismatches;
  }
  CHECK(uv_mismatches == 0);
  for (std::size_t t = 0; t < expected.triangle_count(); ++t) {
    for (std::size_t c = 0; c < 3; ++c) {
      REQUIRE(written.positions[written.triangles[t][c]] == written.positions[expected.triangles[t][c]]);
    }
  }
  // The shapes are the .frig's (on the target's vertices), and move the seam copies with their vertex.
  const Rig glb = LoadRig(folder / "head.glb");
  const Rig frig = LoadRig(folder / "head.frig");
  REQUIRE(glb.shape_count() == frig.shape_count());
  const BlendShapeView jaw = glb.shape(0);
  std::vector<glm::vec3> dense(glb.vertex_count(), glm::vec3(0.0f));
  for (std::size_t i = 0; i < jaw.vertex_indices.size(); ++i) dense[jaw.vertex_indices[i]] = jaw.position_deltas[i];
  for (std::size_t t = 0; t < expected.triangle_count(); ++t) {
    for (std::size_t c = 0; c < 3; ++c) {
      REQUIRE(dense[glb.triangles()[t][c]] == dense[frig.triangles()[t][c]]);
    }
  }
}

TEST_CASE("facerig build: bad command lines and bad input fail clearly and write nothing", "[cli]") {
  const fs::path folder = test::FreshOutputFolder("cli_build_bad");
  const std::string head = DefaultHead().string();
  const std::string out = (folder / "out.glb").string();

  SECTION("usage") {
    CHECK(RunBuildCommand({}).exit_code == 2);
    CHECK(RunBuildCommand({"--template", head, "--target", head}).exit_code == 2);  // no -o
    const test::CommandOutcome mode = RunBuildCommand({"--template", head, "--target", head, "-o", out, "--mode", "magic"});
    CHECK(mode.exit_code == 2);
    CHECK(mode.error_output.find("'magic'") != std::string::npos);
    CHECK(RunBuildCommand({"--template", head, "--target", head, "-o", out, "--units", "inches"}).exit_code == 2);
    // An unknown switch is named, wherever it is (last, it is not taken for an option missing its value).
    for (const std::vector<std::string>& arguments :
         {std::vector<std::string>{"--template", head, "--no-contact", "--target", head, "-o", out},
          std::vector<std::string>{"--template", head, "--target", head, "-o", out, "--no-contact"}}) {
      const test::CommandOutcome unknown = RunBuildCommand(arguments);
      CHECK(unknown.exit_code == 2);
      CHECK(unknown.error_output.find("not expected: --no-contact\n") != std::string::npos);
      CHECK(unknown.error_output.find("facerig build --help") != std::string::npos);  // where the usage is
    }
    const test::CommandOutcome no_value = RunBuildCommand({"--template", head, "--target", head, "-o", out, "--json"});
    CHECK(no_value.exit_code == 2);
    CHECK(no_value.error_output.find("--json: 1 required TEXT missing") != std::string::npos);
  }
  SECTION("a missing target names the file") {
    const test::CommandOutcome outcome =
        RunBuildCommand({"--template", head, "--target", (folder / "missing.obj").string(), "-o", out});
    CHECK(outcome.exit_code == 1);
    CHECK(outcome.error_output.find("missing.obj") != std::string::npos);
  }
  SECTION("an unwritable output fails before any work") {
    const test::CommandOutcome outcome =
        RunBuildCommand({"--template", head, "--target", head, "-o", (folder / "no" / "such" / "dir" / "out.glb").string()});
    CHECK(outcome.exit_code == 1);
    CHECK(outcome.error_output.find("cannot write " + (folder / "no" / "such" / "dir" / "out.glb").string() +
                                    ": the folder " + (folder / "no" / "such" / "dir").string() + " does not exist") !=
          std::string::npos);
    CHECK(outcome.error_output.find("template") == std::string::npos);  // nothing loaded
  }
  SECTION("a target where no face is found suggests a landmark file") {
    const RawRig sheet = RigBuilder::ToRaw(test::MakeGridRig(30, 0));
    WriteObj(folder / "plain.obj", sheet.positions, {}, {}, sheet.triangles, {});
    const test::CommandOutcome outcome = RunBuildCommand({"--template", head, "--target", (folder / "plain.obj").string(), "-o", out});
    INFO(outcome.error_output);
    CHECK(outcome.exit_code == 1);
    CHECK(outcome.error_output.find("--landmarks") != std::string::npos);
  }
  SECTION("a target that is not the template's kind of face: the residual is given") {
    // A flat sheet with landmarks on it: registration cannot make a face of it.
    RawRig sheet = RigBuilder::ToRaw(test::MakeGridRig(40, 0));
    for (glm::vec3& p : sheet.positions) p = p * 0.5f;
    WriteObj(folder / "sheet.obj", sheet.positions, {}, {}, sheet.triangles, {});
    FaceLandmarks landmarks;
    for (std::uint32_t i = 0; i < kDlibLandmarkCount; ++i) {
      landmarks.points.emplace_back(static_cast<float>(i % 9) * 2.0f, static_cast<float>(i / 9) * 2.0f, 0.0f);
      landmarks.indices.push_back(i);
      landmarks.confidence.push_back(1.0f);
    }
    WriteLandmarksJson(folder / "sheet_landmarks.json", landmarks);
    const test::CommandOutcome outcome =
        RunBuildCommand({"--template", head, "--target", (folder / "sheet.obj").string(), "-o", out, "--landmarks",
               (folder / "sheet_landmarks.json").string()});
    INFO(outcome.error_output);
    CHECK(outcome.exit_code == 1);
    // Registration either ends with a residual too large for a face, or its
    // sparse Cholesky finds the degenerate fit not positive definite first:
    // which one depends on rounding (a small change to the template's shape,
    // another CPU's BLAS kernels). Both are clear refusals.
    CHECK((outcome.error_output.find("residual") != std::string::npos ||
           outcome.error_output.find("non-rigid ICP: the solve failed") != std::string::npos));
  }
  CHECK_FALSE(fs::exists(out));
  for (const auto& entry : fs::directory_iterator(folder)) {
    const std::string name = entry.path().filename().string();
    CHECK(name.find("out.glb") == std::string::npos);
    CHECK(name.find(".tmp") == std::string::npos);
  }
}

}  // namespace facerig
