#include "volguide/integrators/guided/walk/trust.h"

#include "volguide/integrators/guided/estimates/allocation.h"

namespace volguide {

GuidedShare TrustRule::guided_share(const TrustPoint& point) const {
    GuidedShare g;
    g.confidence = confidence(point.leaf, point.sigma_t);
    if (point.vertex && g.confidence < kSkipConfidence) {
        g.source = ShareSource::Skipped;
        return g;
    }
    if (point.learned == 0.f) {
        g.source = ShareSource::Unselected;
        return g;
    }
    const bool learned = point.learned != Allocation::kConfigured;
    g.source = learned ? ShareSource::Learned : ShareSource::Configured;
    if (point.kind == DecisionKind::Distance)
        g.undamped = 1.f - (learned ? 1.f - point.learned : settings_.c_T);
    else
        g.undamped = learned ? point.learned : configured_share(point.kind);
    g.share = g.undamped * g.confidence;
    return g;
}

}  // namespace volguide
