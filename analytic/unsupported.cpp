#include "analytic/unsupported.h"

#include "core/error.h"

namespace furnace::analytic {

void unsupported_configuration(const Scene& scene, const std::string& what) {
  throw Error("scene '" + scene.name + "' (" + scene.source + "): " + what +
              " is outside what the analytic references solve exactly.");
}

}  // namespace furnace::analytic
