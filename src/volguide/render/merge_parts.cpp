#include "volguide/render/merge_parts.h"

#include <algorithm>

#include "volguide/core/error.h"

namespace volguide {

namespace {

[[noreturn]] void reject(const NamedPart& p, const std::string& why) {
    throw InputError(SourceLocation{p.file, 0}, "does not belong to the render of " + why);
}

// The first part is the reference every other is checked against.
void check_same_render(const NamedPart& first, const NamedPart& p) {
    const PartInfo &a = first.part.info, &b = p.part.info;
    const std::string of = first.file + ": ";
    // The integrator first: the scene's fingerprint covers its file, the integrator included.
    if (b.integrator != a.integrator)
        reject(p, of + "another integrator configuration (" + b.integrator + " vs " + a.integrator + ")");
    if (b.scene != a.scene)
        reject(p, of + "another scene (" + b.scene_file + ", fingerprint " + b.scene + " vs " + a.scene_file + ", " +
                      a.scene + ")");
    if (b.seed != a.seed) reject(p, of + "another seed (" + std::to_string(b.seed) + " vs " + std::to_string(a.seed) + ")");
    if (b.field != a.field) reject(p, of + "another guiding field (" + b.field + " vs " + a.field + ")");
    if (p.part.mean.width != first.part.mean.width || p.part.mean.height != first.part.mean.height)
        reject(p, of + "another image size");
    if (p.part.variance.pixels.empty() != first.part.variance.pixels.empty())
        reject(p, of + "another kind: one has a variance image, the other not");
}

void check_disjoint(const std::vector<NamedPart>& parts) {
    for (size_t i = 0; i < parts.size(); ++i)
        for (size_t j = 0; j < i; ++j) {
            const SampleRange o = first_overlap(parts[j].part.info.samples, parts[i].part.info.samples);
            if (o.count > 0)
                throw InputError(SourceLocation{parts[i].file, 0},
                                 "samples " + format_ranges({o}) + " are also in " + parts[j].file +
                                     " (parts must hold disjoint sample ranges)");
        }
}

}  // namespace

MergeResult merge_parts(const std::vector<NamedPart>& parts) {
    if (parts.empty()) throw std::invalid_argument("merge: no parts");
    for (const NamedPart& p : parts) check_same_render(parts.front(), p);
    check_disjoint(parts);

    const RenderPart& first = parts.front().part;
    const size_t n = first.mean.pixels.size();
    const bool variance = !first.variance.pixels.empty();
    std::vector<double> weight(n, 0.0), sum(3 * n, 0.0), sum2(variance ? 3 * n : 0, 0.0);
    SampleRanges all;
    // Parts in the order of their first sample: the same sums whatever order the files were given in.
    std::vector<const NamedPart*> order;
    for (const NamedPart& p : parts) order.push_back(&p);
    std::stable_sort(order.begin(), order.end(), [](const NamedPart* a, const NamedPart* b) {
        const auto key = [](const NamedPart* p) { return p->part.info.samples.empty() ? 0 : p->part.info.samples.front().first; };
        return key(a) < key(b);
    });
    for (const NamedPart* np : order) {
        const RenderPart& p = np->part;
        all.insert(all.end(), p.info.samples.begin(), p.info.samples.end());
        for (size_t k = 0; k < n; ++k) {
            const double w = p.weight[k];
            if (w == 0.0) continue;
            weight[k] += w;
            for (int c = 0; c < 3; ++c) {
                const double m = p.mean.pixels[k][c];
                sum[3 * k + c] += w * m;
                if (variance) sum2[3 * k + c] += w * (double(p.variance.pixels[k][c]) + m * m);
            }
        }
    }

    MergeResult result;
    RenderPart& out = result.merged;
    out.info = first.info;
    out.info.samples = normalized(all);
    result.gaps = gaps(out.info.samples);
    out.weight = weight;
    out.mean = Image(first.mean.width, first.mean.height);
    if (variance) out.variance = Image(first.mean.width, first.mean.height);
    for (size_t k = 0; k < n; ++k) {
        if (weight[k] == 0.0) continue;
        const double inv = 1.0 / weight[k];
        for (int c = 0; c < 3; ++c) {
            const double m = sum[3 * k + c] * inv;
            out.mean.pixels[k][c] = float(m);
            if (variance) out.variance.pixels[k][c] = float(std::max(0.0, sum2[3 * k + c] * inv - m * m));
        }
    }
    return result;
}

}  // namespace volguide
