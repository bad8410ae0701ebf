// PLACEHOLDER owned by the `vdb` branch: it defines read_vdb_file with OpenVDB. This stub only
// lets the media branch link before that branch is merged; on merge, take the vdb version.
#include "volguide/core/error.h"
#include "volguide/media/grid_data.h"

namespace volguide {

GridData read_vdb_file(const std::string& path, const std::string& grid_name) {
    throw InputError(SourceLocation{path, 0},
                     fmt::format("\"{}\": cannot read grid \"{}\": OpenVDB support is not built in", path, grid_name));
}

}  // namespace volguide
