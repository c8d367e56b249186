// `facerig photo`: a talking head from one photograph.
#include "cli/commands.h"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <future>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "cli/common.h"
#include "cli/names.h"
#include "cli/obj_folder.h"
#include "cli/options.h"
#include "cli/photo_template.h"
#include "cli/template_info.h"
#include "facerig/offline/photo/skin_mask.h"
#include "facerig/offline/photo/debug.h"
#include "facerig/offline/photo/landmarks.h"
#include "facerig/offline/error.h"
#include "facerig/offline/photo/fit.h"
#include "facerig/offline/photo/image.h"
#include "facerig/offline/photo/rig.h"
#include "facerig/runtime/io/output_set.h"
#include "facerig/runtime/io/rig_file.h"
#include "facerig/runtime/rig_warnings.h"

namespace facerig::cli {
namespace {

constexpr const char* kPhotoDescription =
    "Makes a talking head from one photograph (PNG or JPEG; larger than 2048 px: downscaled): dlib's 68\n"
    "landmarks on the largest face, the template fitted to them (camera, identity and expression weights),\n"
    "the photo baked into the skin's UVs (hidden parts from the mirror side, then the photo's skin colour).\n"
    "The result is the template's whole rig on the fitted face. Without --template: the built-in head,\n"
    "deformed smoothly onto the landmarks; a template folder with identity meshes (ICT-FaceKit's\n"
    "identityNNN.obj) fits the face with them, then refines it by the photo's shading (--no-shading-fit: not).";

struct PhotoOptions {
  std::string image, output, template_path, frig, obj_dir, report, debug_png;
  LandmarkParams landmark_params;
  PhotoLandmarkParams photo_landmarks;
  StandardShapesOptions naming;
  PhotoFitParams fit_params;
  PhotoRigParams rig_params;
};

void AddPhotoOptions(CLI::App& photo, PhotoOptions& options) {
  photo.add_option("IMAGE", options.image, "the photograph (PNG or JPEG)")->required();
  AddOutputOptions(photo, options.output, options.report, "output rig (.glb, .gltf or .frig)");
  photo.add_option("--template", options.template_path,
                   "template: a rig, or a folder of OBJs (identityNNN.obj there: fitted; default: the built-in head)");
  photo.add_option("--frig", options.frig, "also write the rig as .frig");
  photo.add_option("--obj-dir", options.obj_dir, "also write neutral.obj and one OBJ per shape into DIR");
  photo.add_option("--debug-png", options.debug_png,
                   "draw the face box, the landmarks and the fitted model's landmarks over the photo, shaded blue\n"
                   "where the texture takes no photo pixels");
  AddOnOffFlags(photo, "shading-fit", options.fit_params.shading,
                "refine the fitted face by the photo's shading (spherical-harmonic lighting; templates with identity\n"
                "modes)");
  AddOnOffFlags(photo, "delight", options.rig_params.texture.delight,
                "divide the photo's own light (the shading fit's) out of the skin texture: the player lights the\n"
                "head again (needs the shading fit)");
  AddShapePredictorOption(photo, options.landmark_params);
  photo.add_option("--face-cascade", options.photo_landmarks.face_cascade,
                   "OpenCV Haar face cascade, asked when dlib's detector finds no face (\"\": none)")
      ->default_str(options.photo_landmarks.face_cascade.empty() ? std::string("none found")
                                                                   : options.photo_landmarks.face_cascade.string());
  AddShapeNamingOptions(photo, options.naming);
}

// Wall-clock seconds of each step, in order.
class StepTimer {
 public:
  // Each step is also reported to a library caller (StageProgress) as it starts.
  template <typename Body>
  auto Run(const char* name, Body&& body) {
    StageProgress(name, steps_.size(), 0);
    const auto start = std::chrono::steady_clock::now();
    auto value = body();
    steps_.emplace_back(name, SecondsSince(start));
    return value;
  }
  void Add(const char* name, double seconds) { steps_.emplace_back(name, seconds); }
  std::size_t step_count() const { return steps_.size(); }
  std::vector<std::pair<std::string, double>> WithTotal(double total) const {
    auto steps = steps_;
    steps.emplace_back("total", total);
    return steps;
  }

 private:
  std::vector<std::pair<std::string, double>> steps_;
};

void PrintNotes(const std::vector<std::string>& notes) {
  for (const std::string& note : notes) std::fprintf(stderr, "note: %s\n", note.c_str());
}

// The photo's face: its box now, its 68 points once the shape predictor has
// loaded (on another thread meanwhile). LandmarkDetectionError names the image file.
PhotoLandmarks DetectOnPhoto(const PhotoOptions& options, const Photo& photo, std::future<LandmarkDetector>& loading,
                             std::optional<LandmarkDetector>& detector) {
  try {
    PhotoLandmarks face = FindPhotoFace(photo.image, options.photo_landmarks);
    detector.emplace(loading.get());
    PlacePhotoLandmarks(*detector, photo.image, face);
    return face;
  } catch (const LandmarkDetectionError& error) {
    std::string message = error.what();
    if (message.rfind("photo: ", 0) == 0) message.erase(0, 7);
    throw LandmarkDetectionError(options.image + ": " + message, options.image, error.value());
  }
}

// What the command computed, for writing and the report.
struct PhotoRun {
  Photo photo;
  PhotoLandmarks landmarks;
  PhotoTemplate photo_template;
  PhotoFit fit;
  PhotoRig made;
  Rig rig;  // named for writing
  StandardShapesReport names;
};

nlohmann::json PixelsJson(const std::vector<glm::vec2>& pixels, float scale) {
  nlohmann::json list = nlohmann::json::array();
  for (const glm::vec2 p : pixels) list.push_back({p.x / scale, p.y / scale});
  return list;
}

nlohmann::json FitJson(const PhotoFit& fit) {
  nlohmann::json expressions = nlohmann::json::object();
  for (std::size_t e = 0; e < fit.expression_names.size(); ++e) {
    expressions[fit.expression_names[e]] = fit.expression_weights[e];
  }
  return {{"identity_modes", fit.identity_weights.size()},
          {"identity_weights", fit.identity_weights},
          {"expression_weights", expressions},
          {"landmark_rms_pixels", fit.rms_pixels},
          {"deformed", fit.deformed},
          {"camera_scale", fit.camera.scale},
          {"camera_distance", fit.camera_distance}};
}

nlohmann::json TextureJson(const PhotoRig& made, int size) {
  const PhotoTextureStats& stats = made.texture_stats;
  return {{"size", size},
          {"seen_fraction", stats.seen_fraction},
          {"mirrored_fraction", stats.mirrored_fraction},
          {"filled_fraction", stats.filled_fraction},
          {"skin_colour", {made.skin_colour.r, made.skin_colour.g, made.skin_colour.b}},
          {"hair_found", made.hair_found},
          {"hair_colour", {made.hair_colour.r, made.hair_colour.g, made.hair_colour.b}},
          {"hairline_front", stats.hairline_front},
          {"hairline_bins_from_photo", stats.hairline_bins_from_photo},
          {"eye_materials_painted", made.eye_materials_painted}};
}

// The report: landmarks and the face box in the original photo's pixels.
CommandReport PhotoReport(const PhotoOptions& options, const PhotoRun& run) {
  CommandReport report{"photo",
                       {{"image", options.image},
                        {"template", run.photo_template.source},
                        {"shape_predictor", options.landmark_params.shape_predictor.string()}},
                       {{"rig", options.output},
                        {"frig", options.frig},
                        {"obj_dir", options.obj_dir},
                        {"debug_png", options.debug_png}},
                       SpeechAndBlinkWarnings(run.rig)};
  AddShapeNamingWarnings(run.names, report.warnings);
  const Photo& photo = run.photo;
  const ImageFaceBox& box = run.landmarks.box;
  nlohmann::json& result = report.result;
  result["photo"] = {{"width", photo.original_width}, {"height", photo.original_height},
                     {"fitted_width", photo.image.width}, {"fitted_height", photo.image.height},
                     {"scale", photo.scale}, {"grey", photo.grey}};
  std::vector<std::string> notes = photo.notes;
  notes.insert(notes.end(), run.landmarks.notes.begin(), run.landmarks.notes.end());
  result["notes"] = notes;
  result["faces_found"] = run.landmarks.faces_found;
  result["face_detector"] = run.landmarks.detector;
  const double scale = photo.scale;
  result["face_box"] = {box.left / scale, box.top / scale, box.right / scale, box.bottom / scale};
  result["landmarks"] = PixelsJson(run.landmarks.pixels, photo.scale);
  result["template"] = {{"name", run.photo_template.description},
                        {"built_in", run.photo_template.built_in},
                        {"info", TemplateInfoReport(run.photo_template.info)}};
  // As in `facerig build`'s report: null when the template had a tongueOut, or no tongue.
  const std::string& tongue_part = run.photo_template.tongue_out_synthesised_from;
  result["tongue_out_synthesised_from"] = tongue_part.empty() ? nlohmann::json() : nlohmann::json(tongue_part);
  result["fit"] = FitJson(run.fit);
  result["fit"]["lid_margins_fitted"] = run.made.lid_margins_fitted;
  result["texture"] = TextureJson(run.made, PhotoRigParams{}.texture.size);
  result["vertices"] = run.rig.vertex_count();
  result["shapes"] = run.rig.shape_count();
  result["shape_names"] = ShapeNamesJson(options.naming, run.names);
  return report;
}

// Every output under its temporary name, then the report; renamed into place together.
void WritePhotoSet(const PhotoOptions& options, const PhotoRun& run, StepTimer& timer,
                   const std::chrono::steady_clock::time_point start) {
  WriteOutputSet([&](OutputSet& set) {
    StageProgress("write", timer.step_count(), 0);
    const auto write_start = std::chrono::steady_clock::now();
    const std::filesystem::path rig_path =
        WriteWithFilesBeside(set, options.output, [&](const std::filesystem::path& path) { SaveRig(path, run.rig); });
    CheckAfterWrite("rig", rig_path);
    if (const std::filesystem::path frig = AddOptionalFile(set, options.frig); !frig.empty()) {
      SaveRig(frig, run.rig);
      CheckAfterWrite("frig", frig);
    }
    if (!options.obj_dir.empty()) {
      const std::filesystem::path folder = AddObjFolderOutput(set, options.obj_dir);
      WriteRigObjFolder(folder, run.rig);
      CheckAfterWrite("obj-dir", folder);
    }
    if (const std::filesystem::path png = AddOptionalFile(set, options.debug_png); !png.empty()) {
      WritePhotoFitPng(png, ShadeOutsideSkinMask(run.photo.image, run.made.skin_mask), run.landmarks, run.fit);
      CheckAfterWrite("debug-png", png);
    }
    timer.Add("write", SecondsSince(write_start));
    CommandReport report = PhotoReport(options, run);
    report.timings = timer.WithTotal(SecondsSince(start));
    WriteReport(set, options.report, report);
  });
}

void CheckOutputsWritable(const PhotoOptions& options) {
  CheckWritable({options.output, options.frig, options.report, options.debug_png});
  if (!options.obj_dir.empty()) CheckWritable(options.obj_dir);
}

// The photo, its landmarks and the template, each a timed step with a line on stderr.
void ReadAndDetect(const PhotoOptions& options, PhotoRun& run, StepTimer& timer,
                   std::optional<LandmarkDetector>& detector) {
  // dlib's shape predictor takes longer to load than the face takes to find.
  std::future<LandmarkDetector> loading =
      std::async(std::launch::async, [&options] { return LandmarkDetector(options.landmark_params); });
  std::fprintf(stderr, "reading %s...\n", options.image.c_str());
  run.photo = timer.Run("read", [&] { return ReadPhoto(options.image); });
  PrintNotes(run.photo.notes);
  std::fputs("detecting the face and its landmarks...\n", stderr);
  run.landmarks = timer.Run("detect", [&] { return DetectOnPhoto(options, run.photo, loading, detector); });
  PrintNotes(run.landmarks.notes);
  std::fprintf(stderr, "face: %d px at (%d, %d) in the %dx%d image\n",
               std::max(run.landmarks.box.width(), run.landmarks.box.height()), run.landmarks.box.left,
               run.landmarks.box.top, run.photo.image.width, run.photo.image.height);
}

// The template with the seconds its loading took.
struct LoadedTemplate {
  PhotoTemplate loaded;
  double seconds = 0.0;
};

int MakePhotoHead(const PhotoOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  CheckOutputsWritable(options);
  StepTimer timer;
  PhotoRun run;
  // Detection and the template's loading need nothing of each other: the
  // template loads on a second core meanwhile.
  std::fputs("loading the template...\n", stderr);
  std::future<LoadedTemplate> template_load = std::async(std::launch::async, [&options] {
    const auto load_start = std::chrono::steady_clock::now();
    PhotoTemplate loaded = LoadPhotoTemplate(options.template_path, options.naming);
    return LoadedTemplate{std::move(loaded), SecondsSince(load_start)};
  });
  std::optional<LandmarkDetector> detector;
  ReadAndDetect(options, run, timer, detector);
  LoadedTemplate loaded = template_load.get();
  run.photo_template = std::move(loaded.loaded);
  timer.Add("template", loaded.seconds);
  std::fprintf(stderr, "template %s: %zu vertices, %zu shapes, %zu identity modes\n",
               run.photo_template.description.c_str(), run.photo_template.rig.vertex_count(),
               run.photo_template.rig.shape_count(), run.photo_template.identities.size());
  std::fputs("fitting the face...\n", stderr);
  run.fit = timer.Run("fit", [&] {
    const PhotoFaceModel model = BuildPhotoModel(run.photo_template, *detector);
    return FitPhoto(model, run.photo.image, run.landmarks.pixels, options.fit_params);
  });
  std::fprintf(stderr, "fit: landmark residual %.2f px%s\n", run.fit.rms_pixels,
               run.fit.deformed ? " (the head deformed onto the landmarks)" : "");
  std::fputs("baking the photo into the texture...\n", stderr);
  run.made = timer.Run("texture", [&] {
    return MakePhotoRig(run.photo_template.rig, run.photo_template.surface, run.fit, run.photo.image,
                        run.landmarks.pixels, options.rig_params);
  });
  run.rig = NameShapesForWriting(run.made.rig, options.naming, &run.names);
  std::fputs("writing...\n", stderr);
  WritePhotoSet(options, run, timer, start);
  std::printf("wrote %s: %zu vertices, %zu shapes, the photo's texture on the skin (%.0f%% seen, %.0f%% mirrored); "
              "%.2f s\n",
              options.output.c_str(), run.rig.vertex_count(), run.rig.shape_count(),
              100.0 * run.made.texture_stats.seen_fraction, 100.0 * run.made.texture_stats.mirrored_fraction,
              SecondsSince(start));
  return 0;
}

int RunPhoto(const PhotoOptions& options) {
  return RunWritingCommand([&options] { return MakePhotoHead(options); });
}

}  // namespace

void AddPhotoCommand(CLI::App& facerig, CommandBody& body) {
  const auto [photo, options] =
      AddSubcommand(facerig, body, "photo", "a talking head from one photograph", kPhotoDescription, RunPhoto);
  AddPhotoOptions(*photo, *options);
}

}  // namespace facerig::cli
