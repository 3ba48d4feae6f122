// What a leg run writes (layout: benchmarks/RESULTS.md and docs/leg-scenes.md):
// leg.h5 + leg.csv (the sensors' series; /fields the tissue nodes and the skin
// every frame), leg.xdmf (ParaView: tets and skin over time), skin OBJ frames
// and summary.json - each written whole or marked incomplete/failed.
#pragma once

#include "leg/run.hpp"
#include "leg/scene.hpp"
#include "leg/sensors.hpp"

#include "tbio/json.hpp"
#include "tbio/results_file.hpp"

#include <string>
#include <vector>

namespace leg {

/// The results file's /meta for one variant: solver "msd-leg", the scene's
/// text, the constants used, the terms, the knee's control and the geometry.
tbio::RunMeta run_meta(const LegScene& scene, const LegVariant& variant, const msd::LegModel& model);

/// /fields "nodes" (rest positions, tets), "skin" (rest vertices, triangles)
/// and, when there are any, "bones" (the bone surfaces) and "obstacles" (the
/// obstacles drawn, Instruments::obstacles): rest vertices, triangles.
void add_rest_geometry(tbio::ResultsWriter& writer, const msd::LegModel& model, const msd::TriangleMesh& skin,
                       const msd::TriangleMesh& bones, const msd::TriangleMesh& obstacles);

/// One frame's /fields: node, skin, bone and obstacle displacements from rest.
void append_frame_fields(tbio::ResultsWriter& writer, const Frame& frame, const Instruments& in);

/// DIR/skin/frame_NNNN.obj: the embedded skin of frame `index` (micrometres).
void write_skin_obj(const std::string& dir, long index, const msd::Points& skin_x, const msd::TriangleMesh& skin);

/// XDMF for ParaView: the tets, the skin and the bones (bone_vertices > 0),
/// each frame's geometry the rest points plus that frame's displacement (a
/// hyperslab of /fields/NAME_displacement in `h5_name`).
void write_xdmf(const std::string& path, const std::string& h5_name, const std::vector<double>& times, long nodes,
                long tets, long skin_vertices, long skin_triangles, long bone_vertices = 0, long bone_triangles = 0);

/// summary.json of one run.
tbio::Json summary_json(const LegRunSummary& s, const LegScene& scene);

/// out_dir/summary.json over every variant's summary.
void write_variants_summary(const std::string& out_dir, const LegScene& scene,
                            const std::vector<LegRunSummary>& summaries);

}  // namespace leg
