#pragma once
// The Context every GPU command uses: device and validation from the environment (GIMG_DEVICE,
// GIMG_VALIDATION), the chosen device printed with --verbose. Inside `gimg batch` every model's
// command gets the batch's one Context.

#include "commands.h"

#include "gimg/engine/context.h"

#include <memory>

namespace gimg::cli {

// The Context `gimg batch` shares with the commands it runs (empty outside a batch).
inline std::shared_ptr<Context>& shared_batch_context() {
    static std::shared_ptr<Context> context;
    return context;
}

inline std::shared_ptr<Context> open_context(const GlobalOptions& global) {
    if (shared_batch_context()) return shared_batch_context();
    ContextOptions options = ContextOptions::from_environment();
    options.verbose = global.verbose;
    return Context::create(options);
}

}  // namespace gimg::cli
