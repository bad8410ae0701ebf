// field_accuracy SCENE.xml FIELD --from X,Y,Z --dir X,Y,Z [options] [-D name=value ...]: the guiding
// field's accuracy inside a medium (issue 56, item 2). Along the line from --from in direction --dir, the
// first surface it hits bounds the medium it enters (that shape's interior); points at the given depths
// (in mean free paths of the medium's channel-average sigma_t at the entry) up to the exit are probed.
// At each point x, against a brute-force reference (radiance_probe.h: volpath's walk started at x):
//   incident   L~(x, w) = Phi V_L(w)   vs L_i(x, w) on --dirs spherical-Fibonacci directions w
//   inscatter  L~_i(x, d)              vs ∫ f_p(d, w) L_i(x, w) dw on --inscatter-dirs directions d
//   fluence    Phi                     vs 4π × the mean of L_i over the directions
// Each relMSE is mean_k (field_k - ref_k)^2 / mean_k(ref)^2 with the reference's own variance of the
// mean subtracted (so a noisy reference does not count as field error); `shape` relMSEs compare the
// normalised distributions (field / its mean against reference / its mean), and `iso` the same for the
// best isotropic guess (the constant). A field whose shape relMSE is not below iso's predicts no
// direction better than the uniform density. The incident references hold no delta light's direct
// light (a walk never hits a point or spot light); the in-scattered ones do.
// Output: one CSV row per point (stdout or --out). Options: --depths a,b,... (mfp; default
// 0.25,0.5,1,2,3,4,6,8,12,16,24,32), --dirs 64, --inscatter-dirs 16, --spp 256, --seed 1, --max-depth 64,
// --rr-rule bounded, --scene-name NAME (the CSV's first column). The last columns are the leaf's
// directional contrast (vmm_contrast.h; of its VMM and of its indirect VMM).
#include <fmt/format.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <string>
#include <vector>

#include "volguide/core/parallel.h"
#include "volguide/guiding/field_io.h"
#include "volguide/vmm/vmm_contrast.h"
#include "volguide/integrators/volpath/radiance_probe.h"
#include "volguide/render/scene.h"
#include "volguide/scene/loader.h"
#include "volguide/vmm/phase_vmm.h"

namespace {

using namespace volguide;

struct Args {
    std::string scene, field, out, name = "scene";
    Point3f from{0.f};
    Vec3f dir{0.f, 0.f, -1.f};
    std::vector<float> depths{0.25f, 0.5f, 1, 2, 3, 4, 6, 8, 12, 16, 24, 32};
    int dirs = 64, inscatter_dirs = 16, spp = 256, max_depth = 64;
    uint64_t seed = 1;
    std::string rr_rule = "bounded";
    std::map<std::string, std::string> defines;
};

std::vector<float> floats(const std::string& s) {
    std::vector<float> v;
    size_t i = 0;
    while (i <= s.size()) {
        const size_t j = s.find(',', i);
        v.push_back(std::stof(s.substr(i, j == std::string::npos ? std::string::npos : j - i)));
        if (j == std::string::npos) break;
        i = j + 1;
    }
    return v;
}

Vec3f vec3(const std::string& s) {
    const std::vector<float> v = floats(s);
    if (v.size() != 3) throw std::runtime_error("expected X,Y,Z, got '" + s + "'");
    return {v[0], v[1], v[2]};
}

void option(Args& a, const std::string& k, const std::string& v) {
    if (k == "--from") a.from = Point3f(vec3(v));
    else if (k == "--dir") a.dir = normalize(vec3(v));
    else if (k == "--depths") a.depths = floats(v);
    else if (k == "--dirs") a.dirs = std::stoi(v);
    else if (k == "--inscatter-dirs") a.inscatter_dirs = std::stoi(v);
    else if (k == "--spp") a.spp = std::stoi(v);
    else if (k == "--seed") a.seed = std::stoull(v);
    else if (k == "--max-depth") a.max_depth = std::stoi(v);
    else if (k == "--rr-rule") a.rr_rule = v;
    else if (k == "--out") a.out = v;
    else if (k == "--scene-name") a.name = v;
    else if (k == "-D") a.defines[v.substr(0, v.find('='))] = v.substr(v.find('=') + 1);
    else throw std::runtime_error("unknown option " + k);
}

Args parse(int argc, char** argv) {
    if (argc < 3) throw std::runtime_error("usage: field_accuracy SCENE.xml FIELD --from X,Y,Z --dir X,Y,Z [options]");
    Args a;
    a.scene = argv[1];
    a.field = argv[2];
    for (int i = 3; i < argc; i += 2) {
        if (i + 1 >= argc) throw std::runtime_error(std::string("missing value after ") + argv[i]);
        option(a, argv[i], argv[i + 1]);
    }
    return a;
}

// n directions spread evenly over the sphere (spherical Fibonacci): equal solid angle each.
std::vector<Vec3f> sphere_directions(int n) {
    std::vector<Vec3f> d;
    const float golden = float(M_PI) * (3.f - std::sqrt(5.f));
    for (int k = 0; k < n; ++k) {
        const float z = 1.f - (2.f * k + 1.f) / float(n), r = std::sqrt(std::max(0.f, 1.f - z * z));
        d.emplace_back(r * std::cos(golden * k), r * std::sin(golden * k), z);
    }
    return d;
}

// The reference at one point and direction set: per direction the channel-average mean and the
// variance of that mean.
struct Reference {
    std::vector<double> mean, var;
};

template <class Sample>
Reference reference(int n, int spp, const Sample& sample) {
    Reference r{std::vector<double>(size_t(n)), std::vector<double>(size_t(n))};
    parallel_for(0, n, [&](int k) {
        double s = 0, s2 = 0;
        for (int i = 0; i < spp; ++i) {
            const double v = sample(k, i).average();
            s += v, s2 += v * v;
        }
        const double m = s / spp;
        r.mean[size_t(k)] = m;
        r.var[size_t(k)] = std::max(0.0, s2 / spp - m * m) / std::max(1, spp - 1);
    });
    return r;
}

double mean_of(const std::vector<double>& v) {
    double s = 0;
    for (double x : v) s += x;
    return v.empty() ? 0 : s / double(v.size());
}

// relMSE of `field` against the reference, net of the reference's noise; `normalise`: both divided by
// their own means first (the shape alone).
double relmse(const std::vector<double>& field, const Reference& ref, bool normalise) {
    const double mr = mean_of(ref.mean), mf = mean_of(field);
    if (!(mr > 0)) return NAN;
    const double sf = normalise ? (mf > 0 ? 1.0 / mf : 0.0) : 1.0 / mr, sr = 1.0 / mr;
    double e = 0;
    for (size_t k = 0; k < field.size(); ++k) {
        const double d = field[k] * sf - ref.mean[k] * sr;
        e += d * d - ref.var[k] * sr * sr;
    }
    return e / double(field.size());
}

struct Line {
    const Medium* medium = nullptr;
    Point3f entry;
    float t_exit = 0.f, sigma_t = 0.f;
};

Line find_line(const Scene& scene, const Args& a) {
    SurfaceInteraction si;
    if (!scene.intersect(Ray(a.from, a.dir), si) || !si.shape->interior_medium())
        throw std::runtime_error("the line hits no shape with an interior medium");
    Line l;
    l.medium = si.shape->interior_medium();
    l.entry = si.p + a.dir * 1e-4f;
    SurfaceInteraction exit;
    l.t_exit = scene.intersect(Ray(l.entry, a.dir), exit) ? exit.t : 1e30f;
    l.sigma_t = l.medium->eval(l.entry).sigma_t.average();
    return l;
}

struct PointRow {
    float depth;
    Point3f x;
};

void header(std::ostream& os) {
    os << "scene,depth_mfp,x,y,z,leaf,leaf_valid,leaf_samples,leaf_tau,fluence_ref,fluence_field,"
          "incident_relmse,incident_shape_relmse,incident_iso_shape_relmse,inscatter_mean_ref,"
          "inscatter_mean_field,inscatter_relmse,inscatter_shape_relmse,inscatter_iso_shape_relmse,ref_rel_noise,"
          "leaf_contrast,leaf_contrast_indirect\n";
}

std::vector<double> field_values(const std::vector<Vec3f>& dirs, const auto& f) {
    std::vector<double> v;
    for (const Vec3f& w : dirs) v.push_back(f(w).average());
    return v;
}

void probe_point(std::ostream& os, const Scene& scene, const GuidingField& field, const Args& a, const Line& line,
                 const PointRow& p, int index) {
    VolPathSettings vs;
    vs.max_depth = a.max_depth;
    vs.rr_rule = a.rr_rule == "mitsuba" ? RouletteRule::Mitsuba : RouletteRule::Bounded;
    const std::vector<Vec3f> wi = sphere_directions(a.dirs), wd = sphere_directions(a.inscatter_dirs);
    const Reference inc = reference(a.dirs, a.spp, [&](int k, int i) {
        Sampler s(a.seed, uint64_t(index) * 4096 + uint64_t(k), uint64_t(i), 1);
        return incident_radiance_sample(scene, vs, p.x, line.medium, wi[size_t(k)], s);
    });
    const Reference ins = reference(a.inscatter_dirs, a.spp, [&](int k, int i) {
        Sampler s(a.seed, uint64_t(index) * 4096 + uint64_t(k), uint64_t(i), 2);
        return inscattered_radiance_sample(scene, vs, p.x, *line.medium, wd[size_t(k)], s);
    });
    const int li = field.tree().leaf_at(p.x);
    const GuidingLeaf* leaf = li < 0 ? nullptr : &field.leaves()[size_t(li)];
    const PhaseVmm phase = hg_phase_vmm(line.medium->phase().mean_cosine());
    const auto f_inc = field_values(wi, [&](const Vec3f& w) { return field.incident(p.x, w); });
    const auto f_ins = field_values(wd, [&](const Vec3f& d) { return field.inscattered(p.x, d, phase); });
    const std::vector<double> iso_inc(wi.size(), mean_of(inc.mean)), iso_ins(wd.size(), mean_of(ins.mean));
    const Vec3f e = li < 0 ? Vec3f(0.f) : field.tree().leaf_bounds(li).extents();
    const float tau = std::cbrt(std::max(0.f, e.x * e.y * e.z)) * line.sigma_t;
    const double noise = mean_of(inc.var) / std::max(1e-30, mean_of(inc.mean) * mean_of(inc.mean));
    const double contrast = leaf ? directional_contrast(leaf->vmm) : 0.0;
    const double contrast_indirect = leaf && leaf->valid_indirect ? directional_contrast(leaf->vmm_indirect) : 0.0;
    os << fmt::format("{},{},{},{},{},{},{},{},{},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g},{:.4g},"
                      "{:.4g},{:.4g}\n",
                      a.name, p.depth, p.x.x, p.x.y, p.x.z, li, leaf && leaf->valid ? 1 : 0, leaf ? leaf->samples : 0,
                      tau, 4.0 * M_PI * mean_of(inc.mean), leaf ? leaf->fluence.average() : 0.f,
                      relmse(f_inc, inc, false), relmse(f_inc, inc, true), relmse(iso_inc, inc, true), mean_of(ins.mean),
                      mean_of(f_ins), relmse(f_ins, ins, false), relmse(f_ins, ins, true), relmse(iso_ins, ins, true),
                      noise, contrast, contrast_indirect);
    os.flush();
}

int run(const Args& a) {
    LoadOptions load;
    load.defines = a.defines;
    const std::unique_ptr<Scene> scene = load_scene(a.scene, load);
    const GuidingField field = load_field(a.field);
    const Line line = find_line(*scene, a);
    std::ofstream file;
    if (!a.out.empty()) file.open(a.out);
    std::ostream& os = a.out.empty() ? std::cout : file;
    header(os);
    int index = 0;
    for (float d : a.depths) {
        const float t = d / line.sigma_t;
        if (t >= line.t_exit) continue;
        probe_point(os, *scene, field, a, line, {d, line.entry + a.dir * t}, index++);
        std::fprintf(stderr, "field_accuracy: %s depth %g mfp done\n", a.name.c_str(), d);
    }
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    try {
        return run(parse(argc, argv));
    } catch (const std::exception& e) {
        std::fprintf(stderr, "field_accuracy: %s\n", e.what());
        return 1;
    }
}
