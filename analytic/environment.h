// The constant environment's contribution at a receiving point.
#pragma once

#include <optional>

#include "core/scene.h"

namespace furnace::analytic {

// E_env = ∫_{visible sky} L_env cos θ dω at p with unit normal n. With no
// object above p's horizon (every object other than `receiver` has
// max dot(x − p, n) ≤ 0) this is π·L_env (∫ cos θ dω = π over the hemisphere).
// 0 when the environment radiance is 0. Throws furnace::Error (naming the
// object) when an object rises above the horizon: the blocked part is not
// solved yet.
double environment_irradiance(const Scene& scene, const Vec3& p, const Vec3& n, std::optional<size_t> receiver);

}  // namespace furnace::analytic
