// The results file shared by every solver (layout: benchmarks/RESULTS.md).
//
//   /meta    attributes: solver, version, git_revision, spec (text), spec_path,
//            spec_name, created (UTC, ISO 8601), host, status
//            ("incomplete" while running or after a crash, "failed", "complete"), failure (message, when failed)
//   /meta/material  attributes: the material constants actually used
//   /series  equal-length 1-D float64 datasets, each with a "units" attribute
//   /timing  attributes: wall_seconds, steps, dt, threads (+ solver details)
//   /metrics attributes: derived scalars (e.g. first_frequency), optional
//   /fields  optional point sets, each NAME_points (N x 3, reference
//            positions), NAME_time (F), NAME_displacement (F x N x 3), and for
//            a surface NAME_triangles (M x 3): "surface" (the FEM boundary),
//            "nodes" (the MSD nodes, with nodes_tets), "probes" (the FEM
//            solution at the MSD nodes' rest positions; NaN outside its mesh)
//
// The file is created when a run starts with status "running", rows are
// appended and flushed as the run goes, and the status becomes "complete" or
// "failed" at the end. A run killed half-way leaves a readable file whose
// status is still "incomplete": never mistaken for a complete one. A CSV copy of
// /series is written beside it (same name, .csv) as rows arrive.
#pragma once

#include <hdf5.h>

#include <array>
#include <chrono>
#include <fstream>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace tbio {

struct SeriesColumn {
  std::string name;
  std::string units;
};

struct RunMeta {
  std::string solver;
  std::string spec_text, spec_path, spec_name;
  std::vector<std::pair<std::string, double>> material;
  std::vector<std::pair<std::string, std::string>> text;  ///< extra /meta attributes
};

class ResultsWriter {
 public:
  /// Creates (truncates) `path` and its CSV twin.
  ResultsWriter(const std::string& path, const RunMeta& meta, std::vector<SeriesColumn> columns);
  ~ResultsWriter();
  ResultsWriter(const ResultsWriter&) = delete;
  ResultsWriter& operator=(const ResultsWriter&) = delete;

  /// Appends one row (one value per column, in column order).
  void append(const std::vector<double>& row);
  /// Records /timing attributes.
  void set_timing(double wall_seconds, long steps, double dt, int threads);
  /// Adds a numeric /timing attribute (solver details: dofs, Newton iterations...).
  void set_timing_detail(const std::string& key, double value);
  /// Adds a numeric /metrics attribute.
  void set_metric(const std::string& key, double value);
  /// Starts the point set `name` of /fields: its reference points and, for a
  /// surface or a tet mesh, its connectivity (cells of 3 or 4 indices; may be empty).
  void add_point_set(const std::string& name, const std::vector<std::array<double, 3>>& points,
                     const std::vector<std::vector<int>>& cells = {});
  /// Appends one frame of displacements (one per point) to the set `name`.
  void append_frame(const std::string& name, double time, const std::vector<std::array<double, 3>>& displacement);
  /// Adds a text attribute to /meta.
  void set_meta(const std::string& key, const std::string& value);
  /// Marks the run complete (and flushes).
  void finish();
  /// Marks the run failed with `message`, keeping every row written so far.
  void fail(const std::string& message);

  long rows() const { return rows_; }
  const std::string& path() const { return path_; }
  const std::string& csv_path() const { return csv_path_; }

 private:
  void flush();
  std::string path_, csv_path_;
  std::vector<SeriesColumn> columns_;
  hid_t file_ = -1, meta_ = -1, series_ = -1, timing_ = -1, metrics_ = -1, fields_ = -1;
  struct PointSet {
    hid_t time = -1, displacement = -1;
    long frames = 0, points = 0;
  };
  std::map<std::string, PointSet> sets_;
  std::vector<hid_t> datasets_;
  std::vector<std::vector<double>> pending_;
  long rows_ = 0;
  std::ofstream csv_;
  std::chrono::steady_clock::time_point last_flush_;
};

/// Everything in a results file, for comparison, reports and tests.
struct Results {
  std::map<std::string, std::string> meta;       ///< /meta text attributes
  std::map<std::string, double> material;        ///< /meta/material
  std::map<std::string, std::vector<double>> series;
  std::map<std::string, std::string> units;      ///< per series
  std::map<std::string, double> timing;
  std::map<std::string, double> metrics;
  /// /fields point sets: name -> (points, frames); read_point_set loads one.
  std::map<std::string, std::pair<long, long>> point_sets;
  std::string status() const;
};

/// One /fields point set: reference points (N), its triangles (if a
/// surface), frame times (F) and displacements (F x N). A file cut off in the
/// middle of a frame gives the frames that have both a time and displacements.
struct PointSetData {
  std::vector<std::array<double, 3>> points;
  std::vector<std::array<int, 3>> triangles;  ///< NAME_triangles when the set is a surface, else empty
  std::vector<double> time;
  std::vector<std::vector<std::array<double, 3>>> displacement;
};
PointSetData read_point_set(const std::string& path, const std::string& name);

/// Reads a results file. Throws msd::Error naming the file on a missing file or
/// a layout that does not match.
Results read_results(const std::string& path);

/// Library versions used in the metadata.
std::string tissuebench_version();
std::string git_revision();

}  // namespace tbio
