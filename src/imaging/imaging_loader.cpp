// SPDX-License-Identifier: MIT
// The imaging module, loaded on demand by the library.
#include "src/core/module_loader.h"
#include "src/imaging/imaging.h"

namespace infocus::imaging {

Result<const ImagingBackend*> loadImaging(const std::string& purpose) {
    return loadModuleTable<ImagingBackend>("infocus-imaging.so", "infocus_imaging", kImagingAbi,
                                           purpose, "src/imaging");
}

}  // namespace infocus::imaging
