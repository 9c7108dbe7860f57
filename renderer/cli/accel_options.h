// Command-line options that choose and configure an accelerator, shared by render, crosscheck and
// bench.
#pragma once

#include <memory>

#include "renderer/accel/accelerator.h"
#include "renderer/cli/cli_args.h"

namespace kiln {

struct AcceleratorChoice {
    AcceleratorKind kind = AcceleratorKind::Embree;
    EmbreeOptions embree;
    ReferenceBvhOptions reference;

    void addOptions(ArgParser& parser, bool withKind);
    std::unique_ptr<Accelerator> build(const Scene& scene) const;
};

}  // namespace kiln
