// The `facerig` subcommands, each defined in its own cli_<topic>.cpp and
// added to the app by cli_app.cpp. Each run returns 0 ok, 1 failure (message
// on stderr, the previous outputs unchanged), 2 for a bad command line, 128 +
// the signal for a run stopped by SIGINT / SIGTERM. Every --json REPORT has
// the one schema of cli_report.h.
#pragma once

#include "cli/options.h"

namespace facerig::cli {

// --- cli_build.cpp ---
// `build`: --template DIR|RIG --target MESH -o OUT.glb [--frig OUT.frig]
// [--obj-dir DIR] [--mode classic|identity|displacement] [--landmarks LM.json]
// [--json REPORT] [--units mm|cm|m] [--template-topology FIT.frig]
// [--shape-predictor F] [--no-contacts] [--no-eye-fit]: a rig for a new face.
// A cast: --template T --target MESH|DIR... --output-dir DIR [--format glb|gltf|frig]
// [--json SUMMARY] (build_batch.h): many faces in one run, the template's
// work done once; exit 3 when some targets failed.
void AddBuildCommand(CLI::App& facerig, CommandBody& body);

// --- cli_photo.cpp ---
// `photo`: IMAGE -o OUT.glb [--template DIR|RIG] [--frig OUT.frig]
// [--obj-dir DIR] [--json REPORT] [--debug-png P] [--shape-predictor F]
// [--names ..] [--visemes ..]: a talking head from one photograph.
void AddPhotoCommand(CLI::App& facerig, CommandBody& body);

// --- cli_register.cpp ---
// `landmarks`: MESH -o LM.json [--debug-png P] [--json REPORT] [--shape-predictor F].
void AddLandmarksCommand(CLI::App& facerig, CommandBody& body);
// `register`: --template DIR|RIG --target MESH -o FITTED.obj [--landmarks LM.json]
// [--json REPORT] [--shape-predictor F].
void AddRegisterCommand(CLI::App& facerig, CommandBody& body);

// --- cli_identity.cpp ---
// `average`: -o AVG(.obj|.glb|.gltf|.frig) FACE FACE... [--no-align] [--json REPORT].
// FACEs: rigs (.frig/.glb/.gltf/template folder) or OBJs, all of one topology
// and units. The output has the first face's topology, UVs and parts, no shapes.
void AddAverageCommand(CLI::App& facerig, CommandBody& body);
// `caricature`: --rig RIG --average AVG --factor F -o OUT [--keep-deltas]
// [--no-align] [--json REPORT]. F in [-1, 3]: -1 the average, 0 the rig itself,
// 1 twice its difference from the average. Expressions are re-derived by
// deformation transfer unless --keep-deltas.
void AddCaricatureCommand(CLI::App& facerig, CommandBody& body);
// `morph`: --template RIG --target RIG -o OUT [--json REPORT]. A rig with the
// template's neutral, the target's shapes and one more shape, identityMorph,
// that morphs the neutral from the template to the target.
void AddMorphCommand(CLI::App& facerig, CommandBody& body);

// --- cli_inspect.cpp ---
// `inspect`: FILE|DIR [--json REPORT] [folder options].
void AddInspectCommand(CLI::App& facerig, CommandBody& body);
// `convert`: IN OUT [--json REPORT] [folder options]; formats by extension.
void AddConvertCommand(CLI::App& facerig, CommandBody& body);
// `default-head`: OUT_DIR [--preview DIR [--preview-size PX]] [--json REPORT].
void AddDefaultHeadCommand(CLI::App& facerig, CommandBody& body);

// --- cli_align.cpp (only with facerig::espeak: FACERIG_CLI_ALIGN) ---
// `align`: AUDIO (--text "..." | --text-file F) [--voice V] -o TRACK.json
// [--json REPORT]: the transcript's phonemes timed on the recording.
void AddAlignCommand(CLI::App& facerig, CommandBody& body);

}  // namespace facerig::cli
