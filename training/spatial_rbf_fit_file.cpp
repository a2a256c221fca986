// saveSpatialRbfFit (spatial_rbf_fit.hpp), apart from the fit so that the fit links without the
// model file's writer.
#include "io/hdf5_file.hpp"
#include "training/spatial_rbf_fit.hpp"

namespace nmdp {

void saveSpatialRbfFit(const std::string& path, const SpatialRbfFitOutcome& fit) {
  const SpatialRbfFitRecord& r = fit.record;
  const SpatialRbfFunction function(r.parameters);
  h5::File file = h5::File::createAtomic(path);
  writeSpatialRbfModel(file, function, fit.geometry);
  writeRbfFitGroup(file, {r.data, r.settings, formatSpatialRbfFitReport(r), r.seconds, r.from_data, r.warnings,
                          viewOf(r.points), r.fit.loo_error, r.fit.loo_relative});
  file.commit();
}

}  // namespace nmdp
