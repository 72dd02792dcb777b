#include "render/methods.h"

#include "core/error.h"
#include "render/erpt_integrator.h"
#include "render/pmc_er_integrator.h"
#include "render/pmc_hi.h"
#include "render/pmc_ip_integrator.h"
#include "render/pmc_pt_integrator.h"
#include "render/pt_integrator.h"

namespace pmcr {

namespace {

std::vector<MethodOption> pmcIpOptions(bool direct) {
    std::vector<MethodOption> options = {
        {"iterations", "0", "adaptive iterations after the first (0: as many as --spp or --time allow)"},
        {"initial-spp", "4", "samples per pixel of the first, uniform iteration"},
        {"spp-per-iteration", "4", "average samples per pixel of each adaptive iteration (N / pixels)"},
        {"epsilon", "0.01", "defensive weight: every pixel's mixture weight is at least epsilon / pixels"},
        {"min-spp", "1", "pilot samples every pixel gets in every iteration; they alone drive the adaptation"},
        {"variance-radius", "2", "a pixel's weight comes from its neighbours' pilot variance within this radius"},
    };
    if (direct)
        options.push_back({"light-samples", "1", "light samples (and as many BSDF samples) per camera sample"});
    return options;
}

std::vector<MethodOption> pmcIpHiOptions() {
    std::vector<MethodOption> options = pmcIpOptions(false);
    for (MethodOption& o : pmcHiMethodOptions()) {
        // PMC-IP's --iterations counts image-plane iterations; PMC-HI's is per estimate.
        if (o.name == "iterations") o.name = "hi-iterations";
        options.push_back(o);
    }
    options.push_back({"feedback", "on", "seed each pixel's PMC-HI weights from its previous iteration (sec. 6.1)"});
    return options;
}

}  // namespace

const std::vector<MethodInfo>& methods() {
    static const std::vector<MethodInfo> list = {
        {"pt", "path tracing with next-event estimation and MIS (the baseline)", true, {},
         [](const RenderSettings& s) { return std::make_unique<PathTracer>(s, PathTracer::Mode::Full); },
         ""},
        {"direct", "direct lighting only, MIS of light and BSDF sampling (the PMC-HI baseline)", true,
         {{"light-samples", "1", "light samples (and as many BSDF samples) per camera sample"}},
         [](const RenderSettings& s) { return std::make_unique<PathTracer>(s, PathTracer::Mode::Direct); },
         ""},
        {"pmc-ip", "PMC-IP adaptive image-plane sampling over path tracing", true, pmcIpOptions(false),
         [](const RenderSettings& s) { return std::make_unique<PmcIp>(s, PmcIp::Estimator::Full); },
         ""},
        {"pmc-ip-direct", "PMC-IP adaptive image-plane sampling over MIS direct lighting", true,
         pmcIpOptions(true),
         [](const RenderSettings& s) { return std::make_unique<PmcIp>(s, PmcIp::Estimator::Direct); },
         ""},
        {"pmc-hi", "PMC-HI adaptive direct lighting (mixture of BSDF, light and cone sampling)", true,
         pmcHiMethodOptions(),
         [](const RenderSettings& s) { return std::make_unique<PathTracer>(s, PathTracer::Mode::PmcHi); },
         ""},
        {"pmc-ip-hi", "PMC-IP adaptive image-plane sampling over PMC-HI direct lighting, with feedback",
         true, pmcIpHiOptions(),
         [](const RenderSettings& s) { return std::make_unique<PmcIp>(s, PmcIp::Estimator::PmcHi); },
         ""},
        {"erpt", "energy redistribution path tracing (equal deposition, lens and caustic perturbations)",
         true,
         {{"chain-length", "100", "mutations per chain, m"},
          {"mutations-per-pixel", "4", "k: e_d = mean pixel luminance / k, per seed pass (--spp passes)"},
          {"prepass-spp", "4", "path-traced samples per pixel estimating the mean luminance"},
          {"lens-radius", "3", "lens perturbation disk radius in pixels (the paper: a 9x9 square)"},
          {"caustic-theta-min", "0.0001", "caustic perturbation angle, log-uniform from (radians)"},
          {"caustic-theta-max", "0.1", "... to (radians)"},
          {"mutation", "erpt", "erpt (caustic for L..SDE, lens otherwise), mix, lens or caustic"},
          {"caustic-probability", "0.5", "--mutation mix: chance of a caustic perturbation"},
          {"expected-values", "off", "deposit a e_d at the proposal and (1-a) e_d at the current path"},
          {"redistribute", "indirect", "all seed paths, or indirect: the emitter seen directly and direct light at the first hit are deposited at their pixel"},
          {"steps-per-dispatch", "4", "mutations per chain per dispatch"},
          {"filter-proposals", "0", "proposed-mutation filter box radius (ERPT 4.4)", true},
          {"filter-consecutive", "0", "cap on consecutive deposits per pixel (ERPT 4.4)", true}},
         [](const RenderSettings& s) { return std::make_unique<Erpt>(s); }, ""},
        {"pmc-er", "population Monte Carlo energy redistribution: a population of light paths, adapted radii",
         true,
         {{"population", "auto", "light paths in the population; auto = one per 4 pixels, paper = the paper's 5000 per 640x480 pixels (at least 64)"},
          {"mutations", "1", "mutations per member per iteration (paper 16-20; fewer measured better)"},
          {"radii", "5,10,50", "perturbation radii in pixels, 1 to 3, separated by , or / (strategy image: red, green, blue)"},
          {"resample-rate", "0.4", "share of the population eliminated (by remaining energy) and regenerated per iteration"},
          {"epsilon", "0.1", "floor of the radius weights alpha"},
          {"initial-alpha", "uniform", "a new member's radius weights: uniform (the paper) or one weight per radius (',' or '/' between; normalised)"},
          {"adapt-rate", "1", "how far each update moves a member's weights to sec. 4.5's (1: all the way, the paper; 0: they stay fixed)"},
          {"caustic-probability", "0.9", "gamma_caustic: chance of a caustic perturbation where it applies"},
          {"pass-spp", "4", "pool paths per pixel per pass, exactly that many in every pixel (sets the iterations); passes are averaged"},
          {"acceptance", "component", "component: each radius's own transition density (eq. 9); mixture: the density of the whole radius mixture (eq. 8)"},
          {"lifetime", "100", "Q, mutations a member of equal births lives (auto: the mean pool path energy in deposits, as the paper's mutations per iteration imply)"},
          {"refill-rounds", "8", "times a slot left empty by a birth without energy is refilled from the pool at once (1: never)"},
          {"redistribute", "indirect", "indirect: seed paths with at most one scattering vertex are deposited at their pixel, the rest make members; all: every path (the paper)"},
          {"prepass-spp", "4", "path-traced samples per pixel estimating the image energy"},
          {"steps-per-dispatch", "4", "mutations per member per dispatch"},
          {"birth", "equal", "equal: every member starts with the mean path energy Q and floor(U + E/Q) shares; path: the paper's E_remain = E", true}},
         [](const RenderSettings& s) { return std::make_unique<PmcEr>(s); }, ""},
        {"pmc-pt", "population Monte Carlo path tracing: a population of pixels mutated in disks",
         true,
         {{"population", "auto", "members; auto = as many as make --defensive of each step's eye paths the pool's"},
          {"mutations", "16", "TR: mutations per member per resample step"},
          {"radii", "5,10,50", "disk radii in pixels, 1 to 3, separated by , or / (strategy image: red, green, blue)"},
          {"pool-spp", "4", "pool eye paths in every pixel per resample step, stratified with the step's other samples there"},
          {"step-growth", "1.5", "step t is round(G^t) times the first step (pool eye paths and mutations per member); weights ∝ size; 1 = equal steps"},
          {"adapt-every", "1", "resample steps between alpha and beta updates (the paper's 100-200 are steps 1/30 this size)"},
          {"resample-rate", "0.4", "share of the population replaced per step (half pool, half beta)"},
          {"epsilon", "0.01", "floor of the alpha weights"},
          {"defensive", "0.5", "share of each step's eye paths from the stratified pool (uniform)"},
          {"estimator", "steps", "steps: the average of each step's per-pixel averages (unbiased); average: the paper's per-pixel average over all steps", true}},
         [](const RenderSettings& s) { return std::make_unique<PmcPt>(s); }, ""},
    };
    return list;
}

const MethodInfo* findMethod(const std::string& name) {
    for (const auto& m : methods())
        if (m.name == name) return &m;
    return nullptr;
}

void validateMethodOptions(const RenderSettings& settings) {
    const MethodInfo* method = findMethod(settings.method);
    if (!method) throw Error("--method " + settings.method + ": unknown method (see pmcr --help)");
    if (!method->create)
        throw Error("--method " + settings.method + ": not implemented yet (" + method->plannedIn + ")");
    for (const auto& [name, value] : settings.options) {
        bool known = false;
        for (const auto& o : method->options) known = known || o.name == name;
        if (!known) throw Error("--" + name + ": unknown option for --method " + settings.method);
    }
}

}  // namespace pmcr
