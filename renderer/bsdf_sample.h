// A BSDF's sample, in the return convention of estimator.h.
#pragma once

#include "core/vec3.h"

namespace furnace {

struct BsdfSample {
  Vec3 wi_local;
  double weight = 0;           // f·|cos θi| / pdf (for a delta lobe: the lobe's weight)
  double pdf_solid_angle = 0;  // 0 for a delta lobe
  bool delta = false;
  bool transmitted = false;    // wi is on the other side of the surface (wi_local.z < 0)
  // The factor of the transport convention the weight includes (a
  // dielectric's 1/η′² for transmission in the radiance convention; else 1),
  // which Russian roulette divides out so that it never kills a path for it.
  double radiance_scale = 1;
};

}  // namespace furnace
