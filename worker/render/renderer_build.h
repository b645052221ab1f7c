// Which build of the renderer this is: what decides its arithmetic, and so an image's bits.
#pragma once

#include <string>

namespace tessera {

/// "0.1.0 (commit 4658cce0a1b2, GNU 12.2.0, Embree 3.13.5, glibc 2.36)": Tessera's version, the
/// commit it was built from ("-dirty" when built with uncommitted changes, "unknown" outside a
/// git checkout), the compiler, and the Embree and C library it runs with. The same unit gives
/// the same bits on two workers only when these agree (docs/design.md, "The determinism
/// contract": another compiler of the same commit is other arithmetic). A worker registers with
/// it, the server records each job's builds, and a farm image lists them
/// (`tessera:renderer_version`).
std::string renderer_build();

}  // namespace tessera
