#include "postproc/flexible_body.hpp"

#include "common/error.hpp"
#include "common/hdf5.hpp"

namespace nvh::postproc {

std::vector<SignalSource> open_body_columns(const std::filesystem::path& results, const std::string& body,
                                            const std::string& dataset) {
  const std::string path = "/bodies/" + body + "/" + dataset;
  hsize_t columns = 0;
  {
    h5::File file = h5::File::open_read(results);
    const h5::Group& root = file.root();
    if (!root.exists(path)) {
      std::string bodies;
      if (root.exists("bodies"))
        for (const std::string& b : root.open_group("bodies").members())
          if (root.exists("bodies/" + b + "/" + dataset)) bodies += (bodies.empty() ? "" : ", ") + b;
      throw Error(results.string() + ": no dataset " + path + "; expected the flexible body '" + body +
                  "' of solve's results (flexible bodies in the file: " +
                  (bodies.empty() ? std::string("none") : bodies) + ")");
    }
    const std::vector<hsize_t> shape = root.shape(path);
    if (shape.size() != 2 || shape[1] == 0)
      throw Error(results.string() + ":" + path + ": expected a (samples, modes) dataset");
    columns = shape[1];
  }
  std::vector<SignalSource> sources;
  for (hsize_t j = 0; j < columns; ++j)
    sources.push_back(SignalSource::open(results.string() + ":" + path + "[" + std::to_string(j) + "]"));
  return sources;
}

std::vector<SignalSource> open_frame_columns(const std::filesystem::path& results, const std::string& body,
                                             const std::vector<std::pair<std::string, int>>& datasets,
                                             const SignalSource& reference) {
  const std::string prefix = results.string() + ":/bodies/" + body + "/";
  std::vector<SignalSource> frame;
  for (const auto& [dataset, columns] : datasets)
    for (int c = 0; c < columns; ++c)
      frame.push_back(SignalSource::open(prefix + dataset + "[" + std::to_string(c) + "]"));
  for (const SignalSource& s : frame)
    if (s.size() != reference.size() || s.info().sample_rate_hz != reference.info().sample_rate_hz)
      throw Error("'" + s.info().address + "' (" + std::to_string(s.size()) +
                  " samples) is not sampled with '" + reference.info().address + "' (" +
                  std::to_string(reference.size()) + " samples)");
  return frame;
}

SuperelementFile read_body_surface(const std::filesystem::path& superelement,
                                   const std::filesystem::path& results, const std::string& body,
                                   Eigen::Index modes) {
  SuperelementFile se = read_superelement(superelement);
  const std::string file = superelement.string();
  if (!se.surface || se.surface->labels.empty())
    throw Error(file +
                ": no /surface; expected a volume component's exported surface ([surface] export = true "
                "in the component file, docs/hdf5-format.md)");
  if (!se.orthonormalized && se.rigid_body_modes_contained > 0)
    throw Error(file + ": a raw " + se.method +
                " basis (rigid_body_modes_contained = " + std::to_string(se.rigid_body_modes_contained) +
                "): solve's modal velocities refer to the elastic modes it derives from it; expected an "
                "orthonormalized superelement (condense's default)");
  if (modes > se.size())
    throw Error(results.string() + ":/bodies/" + body + ": " + std::to_string(modes) + " coordinates, but " +
                file + " has " + std::to_string(se.size()) + "; expected the superelement of body '" + body +
                "'");
  return se;
}

}  // namespace nvh::postproc
