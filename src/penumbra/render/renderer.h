#pragma once
/// The progressive render loop: passes of samples over the whole image, tiles on all cores,
/// each pixel sample independent of scheduling.
#include "penumbra/render/render_stats.h"

namespace penumbra {

class RenderJob;
class SamplingIntegrator;

/// Renders job.film with `integrator` in passes: pass k takes sample indices [a_k, b_k) of every
/// pixel, so after it every pixel has b_k samples. A sample's random numbers depend only on
/// (pixel, sample index, seed) and each pixel sums its samples in index order, so the image is
/// bit-identical for any thread count and any pass schedule. Runs integrator.preprocess first
/// and integrator.end_pass after each pass; stops at the job's spp, at its time limit (before a
/// pass that would not fit), at its error target, or when cancelled (keeping finished tiles).
RenderStats render_passes(RenderJob& job, SamplingIntegrator& integrator);

}  // namespace penumbra
