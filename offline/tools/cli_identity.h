// `facerig average`, `facerig caricature` and `facerig morph` (average face,
// caricature, identity morph): kept out of facerig_cli.cpp, which dispatches
// to them. Each body returns 0 ok, 1 failure (message on stderr, no output
// file written), 2 for an output name that cannot hold the result.
#pragma once

#include "cli_options.h"

namespace facerig::cli {

// Adds `average`: -o AVG(.obj|.glb|.gltf|.frig) FACE FACE... [--no-align] [--json REPORT].
// FACEs: rigs (.frig/.glb/.gltf/template folder) or OBJs, all of one topology
// and units. The output has the first face's topology, UVs and parts, no shapes.
void AddAverageCommand(CLI::App& facerig, CommandBody& body);

// Adds `caricature`: --rig RIG --average AVG --factor F -o OUT [--keep-deltas]
// [--no-align] [--json REPORT]. F in [-1, 3]: -1 the average, 0 the rig itself,
// 1 twice its difference from the average. Expressions are re-derived by
// deformation transfer unless --keep-deltas.
void AddCaricatureCommand(CLI::App& facerig, CommandBody& body);

// Adds `morph`: --template RIG --target RIG -o OUT [--json REPORT]. A rig with
// the template's neutral, the target's shapes and one more shape,
// identityMorph, that morphs the neutral from the template to the target.
void AddMorphCommand(CLI::App& facerig, CommandBody& body);

}  // namespace facerig::cli
