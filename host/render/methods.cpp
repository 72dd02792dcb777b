#include "render/methods.h"

#include "core/error.h"
#include "methods/bdpt/bdpt_integrator.h"
#include "methods/erpt/erpt_integrator.h"
#include "methods/mlt/mlt_integrator.h"
#include "methods/mmlt/mmlt_integrator.h"
#include "methods/pm/pm_integrator.h"
#include "methods/pmc_er/pmc_er_integrator.h"
#include "methods/pmc_ip/pmc_ip_integrator.h"
#include "methods/pmc_pt/pmc_pt_integrator.h"
#include "methods/pssmlt/pssmlt_integrator.h"
#include "methods/pt/pt_integrator.h"

namespace pmcr {

const std::vector<MethodInfo>& methods() {
    // In --help order; each entry is defined in its method's folder under host/methods/.
    static const std::vector<MethodInfo> list = {
        ptMethod(),
        directMethod(),
        bdptMethod(),
        pmcIpMethod(),
        pmcIpDirectMethod(),
        pmcHiMethod(),
        pmcIpHiMethod(),
        erptMethod(),
        pmcErMethod(),
        pmcPtMethod(),
        mltMethod(),
        pssmltMethod(),
        mmltMethod(),
        pmMethod(),
        pmPmcMethod(),
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
