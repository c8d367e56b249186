#include "cli/photo_template.h"

#include <optional>
#include <system_error>
#include <utility>

#include "cli/common.h"
#include "facerig/offline/default_head/default_head.h"
#include "facerig/offline/io/template_folder.h"
#include "facerig/offline/photo/rig.h"
#include "facerig/offline/rigging/tongue_out.h"
#include "facerig/runtime/io/obj.h"
#include "facerig/runtime/io/rig_file.h"

namespace facerig::cli {
namespace {

namespace fs = std::filesystem;

// A template folder: its rig, and its neutral OBJ's own surface (the rig
// keeps one UV per vertex; the OBJ has the seams).
PhotoTemplate FromTemplateFolder(const fs::path& folder) {
  PhotoTemplate loaded;
  TemplateImportReport report;
  loaded.rig = LoadTemplateRig(folder, &report);
  loaded.surface = GroupedByPart(ReadObj(report.neutral_path));
  loaded.identities = LoadIdentityMeshes(folder, loaded.rig.vertex_count());
  return loaded;
}

PhotoTemplate FromRigFile(const fs::path& path) {
  PhotoTemplate loaded;
  loaded.rig = LoadRigOrTemplateFolder(path);
  loaded.surface = NeutralMesh(loaded.rig);
  return loaded;
}

PhotoTemplate BuiltInHead() {
  const fs::path path = BuiltInHeadPath();
  if (path.empty()) {
    PhotoTemplate made;
    made.rig = BuildDefaultHead();
    made.surface = NeutralMesh(made.rig);
    made.info = DefaultHeadTemplateInfo(made.rig);
    made.description = "the built-in head (made in memory: no default_head.frig found)";
    made.built_in = true;
    return made;
  }
  PhotoTemplate loaded = FromRigFile(path);
  loaded.info = ResolveFaceTemplateInfo(loaded.rig, path);
  loaded.source = path.string();
  loaded.description = "the built-in head (" + path.string() + ")";
  loaded.built_in = true;
  return loaded;
}

}  // namespace

fs::path BuiltInHeadPath() {
  std::error_code error;
  const fs::path executable = fs::read_symlink("/proc/self/exe", error);
  if (!error) {
    const fs::path installed = (executable.parent_path() / FACERIG_INSTALLED_HEAD_FROM_BINDIR).lexically_normal();
    if (fs::is_regular_file(installed, error)) return installed;
  }
  const fs::path build_tree = FACERIG_DEFAULT_HEAD;
  if (fs::is_regular_file(build_tree, error)) return build_tree;
  return {};
}

PhotoTemplate LoadPhotoTemplate(const std::string& template_path, const StandardShapesOptions& naming) {
  PhotoTemplate loaded;
  if (template_path.empty()) {
    loaded = BuiltInHead();
  } else {
    loaded = fs::is_directory(template_path) ? FromTemplateFolder(template_path) : FromRigFile(template_path);
    loaded.info = ResolveFaceTemplateInfo(loaded.rig, template_path);
    loaded.source = template_path;
    loaded.description = template_path;
  }
  // Baked visemes are made again from the fitted head's shapes.
  if (naming.visemes == VisemeTargets::kOculus) loaded.rig = WithoutBakedVisemes(loaded.rig);
  SynthesisedTongueOut tongue_out;
  if (std::optional<Rig> with_tongue_out = WithSynthesisedTongueOut(loaded.rig, loaded.info, &tongue_out)) {
    loaded.rig = std::move(*with_tongue_out);
    loaded.tongue_out_synthesised_from = tongue_out.part;
  }
  return loaded;
}

PhotoFaceModel BuildPhotoModel(PhotoTemplate& photo_template, LandmarkDetector& detector) {
  (void)TemplateLandmarkVertices(photo_template.rig, photo_template.info, detector);
  return BuildPhotoFaceModel(photo_template.rig, photo_template.info, photo_template.identities,
                             PhotoModelParamsFor(photo_template.rig), &detector);
}

}  // namespace facerig::cli
