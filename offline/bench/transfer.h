// facerig-bench transfer: deformation transfer (classic and identity-gradient
// modes) and displacement matrices of the whole ICT rig onto random
// same-topology ICT identities: timing (factorization + all expressions) and
// the error table (relative error, leak, eyelid closure).
#pragma once

int RunTransferBenchmark(int argc, char** argv);
