#pragma once
// The Context every GPU command uses: device and validation from the environment (GIMG_DEVICE,
// GIMG_VALIDATION), the chosen device printed with --verbose; inside `gimg batch`, the batch's one
// Context (GlobalOptions::context).

#include "commands.h"

#include "gimg/engine/context.h"

#include <memory>

namespace gimg::cli {

inline std::shared_ptr<Context> open_context(const GlobalOptions& global) {
    if (global.context) return global.context;
    ContextOptions options = ContextOptions::from_environment();
    options.verbose = global.verbose;
    return Context::create(options);
}

}  // namespace gimg::cli
