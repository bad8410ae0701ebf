#pragma once
// The cost model of guided_volpath's decisions: counted work (volpath/work.h) times per-unit weights
// in nanoseconds of one core, fitted by least squares to measured CPU time per sample over the
// benchmark scenes and methods (bench/fit_cost_model.py prints the table below and checks the model
// against measured time per sample; the fit and its check: bench/RESULTS.md). The counts, not the
// clock, drive decisions: a cost is a pure function of what a path did, the same for any thread count
// and scheduling, so the allocation learned from it is too.
#include <array>

#include "volguide/integrators/volpath/work.h"

namespace volguide {

class CostModel {
  public:
    // The fitted weights (cost_model.cpp).
    static CostModel fitted();
    explicit CostModel(const std::array<double, kWorkUnits>& ns) : ns_(ns) {}
    double ns(Work unit) const { return ns_[size_t(unit)]; }
    // The modelled time of `work`, in ns.
    double cost(const WorkCounts& work) const { return sum(work, kWorkUnits); }
    // The walk's part of it (the units before Work::GuidedSegment): what the decision that did `work`
    // costs without its guided part — the unguided decision's cost in its place.
    double unguided_cost(const WorkCounts& work) const { return sum(work, size_t(Work::GuidedSegment)); }

  private:
    double sum(const WorkCounts& work, size_t units) const {
        double c = 0.0;
        for (size_t k = 0; k < units; ++k) c += ns_[k] * double(work.n[k]);
        return c;
    }
    std::array<double, kWorkUnits> ns_;
};

}  // namespace volguide
