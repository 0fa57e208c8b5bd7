// saccade recognize --model A.pcd,B.pcd,...: several models searched in one scene as one
// library (core/library.h); every instance names its model.
#include "daemon/cli/recognize_library.h"

#include "core/fail.h"
#include "core/library.h"
#include "daemon/exit_codes.h"
#include "io/base/json.h"
#include "io/formats/cloud_io.h"
#include "io/sources/model_source.h"

#include <iomanip>
#include <memory>
#include <ostream>

namespace saccade {

void PrintInstance(std::size_t index, const Detection& d, const std::string& model_name,
                   std::ostream& out) {
  out << "instance " << index << ": " << (model_name.empty() ? "" : model_name + ", ") << "votes "
      << d.votes << ", centroid (" << d.centroid_m.x() << ", " << d.centroid_m.y() << ", "
      << d.centroid_m.z() << ") m";
  if (d.fitness >= 0) out << ", fitness " << d.fitness << ", coverage " << d.coverage;
  if (d.colour_agreement >= 0) out << ", colour " << d.colour_agreement;
  if (d.confidence >= 0) out << ", confidence " << d.confidence;
  out << ", pose model->scene:\n";
  for (int row = 0; row < 4; ++row) {
    out << "  ";
    for (int c = 0; c < 4; ++c) out << std::setw(10) << d.model_to_scene(row, c);
    out << "\n";
  }
}

int RecognizeLibraryCommand(const std::vector<std::string>& specs, const Cloud& scene,
                            const SceneQuery& query, const RecognitionOptions& options,
                            const ParallelFor& parallel, bool json, std::ostream& out,
                            std::ostream& err) {
  std::vector<std::unique_ptr<ModelDescription>> models;
  std::vector<const ModelDescription*> library_models;
  std::vector<std::string> names;
  for (const std::string& spec : specs) {
    std::string error;
    std::optional<std::vector<Cloud>> views = LoadModelViews(spec, &error);
    std::optional<ModelDescription> d;
    if (views) d = DescribeModel(*views, options, &error, options.library_radius_ratio);
    if (!d) {
      err << "saccade recognize: " << OneLine(views ? spec + ": " + error : error) << "\n";
      return kExitFailure;
    }
    models.push_back(std::make_unique<ModelDescription>(std::move(*d)));
    library_models.push_back(models.back().get());
    names.push_back(ModelShortName(spec));
  }
  const Library library(library_models, options);
  std::string error;
  const LibraryResult r = RecognizeLibrary(library, scene, query, options, {}, parallel, &error);
  if (!error.empty()) {
    err << "saccade recognize: " << error << "\n";
    return kExitFailure;
  }
  if (json) {
    JsonWriter j;
    j.BeginObject().Key("models").BeginArray();
    for (std::size_t m = 0; m < names.size(); ++m)
      j.BeginObject()
          .Key("name")
          .Value(names[m])
          .Key("file")
          .Value(specs[m])
          .Key("size_m")
          .Value(double(models[m]->scale().size_m))
          .EndObject();
    j.EndArray().Key("scene_descriptions").Value(r.scene_descriptions);
    j.Key("instances").BeginArray();
    for (const Detection& d : r.instances) {
      j.BeginObject().Key("model").Value(names[std::size_t(d.model)]).Key("pose").BeginArray();
      for (int row = 0; row < 4; ++row)
        for (int c = 0; c < 4; ++c) j.Value(double(d.model_to_scene(row, c)));
      j.EndArray().Key("votes").Value(d.votes).Key("centroid").Vector3(d.centroid_m);
      j.Key("confidence").Value(double(d.confidence)).EndObject();
    }
    j.EndArray().Key("timing_ms").BeginObject();
    j.Key("describe").Value(r.describe_ms).Key("match").Value(r.match_ms);
    j.Key("group").Value(r.group_ms).Key("verify").Value(r.verify_ms).EndObject().EndObject();
    out << j.str() << "\n";
    return kExitOk;
  }
  out << std::fixed << std::setprecision(4) << "library: " << names.size() << " models, "
      << r.scene_descriptions << " description(s) of the scene\n"
      << r.instances.size() << " instance(s)\n";
  for (std::size_t i = 0; i < r.instances.size(); ++i) {
    PrintInstance(i, r.instances[i], names[std::size_t(r.instances[i].model)], out);
  }
  out << std::setprecision(2) << "timing ms: describe " << r.describe_ms << " match " << r.match_ms
      << " group " << r.group_ms << " verify " << r.verify_ms << "\n";
  return kExitOk;
}

}  // namespace saccade
