// The one refusal of every analytic reference: a scene, receiver or query
// outside what the closed forms and exact quadratures solve.
#pragma once

#include <string>

#include "core/scene.h"

namespace furnace::analytic {

// Throws furnace::Error: "scene '<name>' (<source>): <what> is outside what
// the analytic references solve exactly."
[[noreturn]] void unsupported_configuration(const Scene& scene, const std::string& what);

}  // namespace furnace::analytic
