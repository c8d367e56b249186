// facerig-bench mouth: ICT-FaceKit's shapes built onto the built-in head
// (another topology, detected landmarks), its opened mouth measured
// (measure/mouth_interior.h: the curtain of upper lip and palate following
// the jaw, the fold under the lower lip at jawOpen 1) against the head's own
// jawOpen and the same build mapped without the mouth's sides; optionally
// close-up renders of the opened mouth.
#pragma once

int RunMouthBenchmark(int argc, char** argv);
