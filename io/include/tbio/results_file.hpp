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
// The file and its CSV copy of /series (same name, .csv) are written under
// temporary names unique to the process (NAME.h5.partial-PID,
// NAME.csv.partial-PID) with status "incomplete"; rows are appended and
// flushed as the run goes; finish() marks it "complete", fail() "failed" with
// the reason, and both close the files and rename them into place. So the
// real name only ever holds a finished or a failed run, an existing file is
// untouched until then, and a process killed half-way (SIGKILL) leaves its
// readable temporary marked "incomplete" beside it. The writer takes an
// exclusive lock (NAME.h5.lock, msd/io/output_lock.hpp) for its life: a second
// writer to the same file is refused. A write that fails (a full disk) throws
// tbio::WriteError; fail() then keeps what it can or removes the temporaries.
#pragma once

#include "msd/core/types.hpp"

#include <hdf5.h>

#include <array>
#include <chrono>
#include <fstream>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace msd {
class OutputLock;
class RegisteredTemporary;
}  // namespace msd

namespace tbio {

/// A results file could not be written (disk full, file size limit, I/O error).
struct WriteError : msd::Error {
  using msd::Error::Error;
};

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

/// What a writer has written so far (every /series value and /fields frame),
/// carried by a checkpoint so a resumed run writes the same file.
struct ResultsSnapshot {
  std::vector<std::vector<double>> rows;
  struct Frames {
    std::vector<double> time;
    std::vector<std::vector<std::array<double, 3>>> displacement;
  };
  std::map<std::string, Frames> fields;
};

class ResultsWriter {
 public:
  /// Locks `path`, then creates the temporaries of `path` and its CSV twin.
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
  /// Marks the run complete, closes the files and renames them into place.
  /// Throws WriteError (the temporaries removed) when that cannot be done.
  void finish();
  /// Marks the run failed with `message`, keeping every row written so far,
  /// closes and renames into place. Never throws: returns false when the file
  /// could not be written (a full disk); then the temporaries are removed and
  /// nothing is left.
  bool fail(const std::string& message);
  /// Everything written so far (flushes first).
  ResultsSnapshot snapshot();
  /// Appends the rows and frames of `s` (the point sets must exist).
  void restore(const ResultsSnapshot& s);

  long rows() const { return rows_; }
  const std::string& path() const { return path_; }
  const std::string& csv_path() const { return csv_path_; }
  const std::string& temporary_path() const { return tmp_path_; }

 private:
  void flush();
  void create_layout(const RunMeta& meta);
  void close_handles();
  void discard();
  void commit();
  std::string path_, csv_path_, tmp_path_, tmp_csv_path_;
  std::unique_ptr<msd::OutputLock> lock_;
  std::unique_ptr<msd::RegisteredTemporary> tmp_registered_, csv_registered_;
  bool open_ = false;
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

/// True when a results file on a full disk could not even be closed: HDF5's
/// state is then damaged and shutting it down (at exit, or in MPI_Finalize)
/// would crash. The program then ends with std::_Exit after flushing its
/// output (end_program).
bool hdf5_damaged();

/// A program's last step: returns `rc` for main() to return, or, when
/// hdf5_damaged(), flushes stdout and stderr and ends the process at once with
/// `rc` (std::_Exit), skipping the HDF5 shutdown that would crash. The
/// temporaries of a failed file are gone by then.
int end_program(int rc);

/// Library versions used in the metadata.
std::string tissuebench_version();
std::string git_revision();

}  // namespace tbio
