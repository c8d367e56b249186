// facerig-bench proportions: a head's face proportions (dlib's 68 points on a
// front render, ratios to the eye distance: nose length and width, eye
// opening, mouth width, lower-face height, face width) next to ICT-FaceKit's
// random identities, their mean and SD, and the head's z-score per ratio
// (issue 34: the built-in head within two SD of real faces).
#pragma once

int RunProportionsBenchmark(int argc, char** argv);
