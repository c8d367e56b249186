// facerig-bench photo: the whole `facerig photo` command on a portrait
// (by default Debian's astronaut, enlarged to 1024 px) with a template that
// has identity modes, timed per step over several runs, with and without the
// shading refinement (the previous pipeline), against the 5 s target.
#pragma once

int RunPhotoBenchmark(int argc, char** argv);
