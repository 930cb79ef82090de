// The queues one worker thread reuses from wave to wave: path state, the
// ray queues of the current and next depth (double-buffered by parity),
// hits, shadow rays, hemisphere rays and continuation candidates.
#pragma once

#include "streams.h"

namespace pt::wf {

struct WaveBuffers {
  PathState paths;
  RayQueue rays[2];
  HitQueue hits;
  ShadowQueue shadows;
  ShadowQueue hemisphere;
  RayQueue continuations;

  size_t bytes() const {
    return paths.bytes() + rays[0].bytes() + rays[1].bytes() + hits.bytes() + shadows.bytes() + hemisphere.bytes() +
           continuations.bytes();
  }
};

}  // namespace pt::wf
