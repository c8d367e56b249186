// MTL material libraries: parsing, and writing what was parsed, which must
// read back as the same materials.
#include <cstdlib>
#include <string>
#include <vector>

#include "facerig/runtime/error.h"
#include "facerig/runtime/io/mtl.h"
#include "fuzz_input.h"

namespace {

// FormatMtl of the parsed materials read back: the same count, names (as
// MtlMaterialNames made them), colours and alpha modes.
void CheckWrittenReadsBack(const std::vector<facerig::MtlMaterial>& parsed) {
  std::vector<facerig::Material> materials;
  for (const facerig::MtlMaterial& entry : parsed) materials.push_back(entry.material);
  const std::vector<std::string> names = facerig::MtlMaterialNames(materials);
  const std::vector<facerig::MtlMaterial> again =
      facerig::ParseMtl(facerig::FormatMtl(materials, names, {}), "written.mtl");
  if (again.size() != materials.size()) std::abort();
  for (std::size_t m = 0; m < again.size(); ++m) {
    if (again[m].material.name != names[m] || again[m].material.base_colour != materials[m].base_colour ||
        again[m].material.alpha_mode != materials[m].alpha_mode) {
      std::abort();
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::vector<facerig::MtlMaterial> parsed;
  try {
    parsed = facerig::ParseMtl(facerig::fuzz::Text(data, size), "input.mtl");
  } catch (const facerig::IoError&) {
    return 0;
  }
  CheckWrittenReadsBack(parsed);
  facerig::SplitMtllibNames(facerig::fuzz::Text(data, size));
  return 0;
}
