#include "tbio/results_file.hpp"

#include "tbio/build_info.hpp"
#include "msd/core/types.hpp"
#include "msd/io/atomic_file.hpp"
#include "msd/io/interrupt.hpp"
#include "msd/io/output_lock.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <iomanip>
#include <sstream>

namespace tbio {

std::string tissuebench_version() { return TISSUEBENCH_VERSION; }
std::string git_revision() { return TISSUEBENCH_GIT_REVISION; }

namespace {

bool g_hdf5_damaged = false;

void check(herr_t status, const std::string& what, const std::string& path) {
  if (status < 0) throw WriteError(path + ": HDF5 error while " + what + " (disk full or file size limit?)");
}

hid_t check_id(hid_t id, const std::string& what, const std::string& path) {
  if (id < 0) throw WriteError(path + ": HDF5 error while " + what + " (disk full or file size limit?)");
  return id;
}

hid_t string_type() {
  const hid_t t = H5Tcopy(H5T_C_S1);
  H5Tset_size(t, H5T_VARIABLE);
  H5Tset_cset(t, H5T_CSET_UTF8);
  return t;
}

void write_text_attr(hid_t obj, const std::string& name, const std::string& value,
                     const std::string& path) {
  if (H5Aexists(obj, name.c_str()) > 0) H5Adelete(obj, name.c_str());
  const hid_t type = string_type();
  const hid_t space = H5Screate(H5S_SCALAR);
  const hid_t attr = check_id(H5Acreate2(obj, name.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT),
                              "creating attribute " + name, path);
  const char* c = value.c_str();
  check(H5Awrite(attr, type, &c), "writing attribute " + name, path);
  H5Aclose(attr);
  H5Sclose(space);
  H5Tclose(type);
}

void write_number_attr(hid_t obj, const std::string& name, double value, const std::string& path) {
  if (H5Aexists(obj, name.c_str()) > 0) H5Adelete(obj, name.c_str());
  const hid_t space = H5Screate(H5S_SCALAR);
  const hid_t attr = check_id(
      H5Acreate2(obj, name.c_str(), H5T_IEEE_F64LE, space, H5P_DEFAULT, H5P_DEFAULT),
      "creating attribute " + name, path);
  check(H5Awrite(attr, H5T_NATIVE_DOUBLE, &value), "writing attribute " + name, path);
  H5Aclose(attr);
  H5Sclose(space);
}

std::string utc_now() {
  const std::time_t t = std::time(nullptr);
  std::tm tm{};
  gmtime_r(&t, &tm);
  std::ostringstream s;
  s << std::put_time(&tm, "%Y-%m-%dT%H:%M:%SZ");
  return s.str();
}

std::string host_name() {
  char buf[256] = {0};
  if (gethostname(buf, sizeof buf - 1) != 0) return "unknown";
  return buf;
}

}  // namespace

ResultsWriter::ResultsWriter(const std::string& path, const RunMeta& meta,
                             std::vector<SeriesColumn> columns)
    : path_(path), columns_(std::move(columns)), pending_(columns_.size()) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);  // errors are reported by us
  const std::filesystem::path p(path);
  csv_path_ = (p.parent_path() / p.stem()).string() + ".csv";
  lock_ = std::make_unique<msd::OutputLock>(path, msd::this_command_line());
  tmp_path_ = msd::create_partial(path);
  tmp_registered_ = std::make_unique<msd::RegisteredTemporary>(tmp_path_);
  try {
    tmp_csv_path_ = msd::create_partial(csv_path_);
  } catch (...) {
    std::filesystem::remove(tmp_path_);
    throw;
  }
  csv_registered_ = std::make_unique<msd::RegisteredTemporary>(tmp_csv_path_);
  open_ = true;
  try {
    create_layout(meta);
  } catch (...) {
    discard();
    throw;
  }
}

void ResultsWriter::create_layout(const RunMeta& meta) {
  const std::string& path = path_;
  file_ = check_id(H5Fcreate(tmp_path_.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT),
                   "creating the file (is the folder writable?)", path);
  meta_ = H5Gcreate2(file_, "meta", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  series_ = H5Gcreate2(file_, "series", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  timing_ = H5Gcreate2(file_, "timing", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  metrics_ = H5Gcreate2(file_, "metrics", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT);
  check_id(meta_ < 0 || series_ < 0 || timing_ < 0 || metrics_ < 0 ? -1 : 0, "creating groups", path);
  write_text_attr(meta_, "solver", meta.solver, path);
  write_text_attr(meta_, "version", tissuebench_version(), path);
  write_text_attr(meta_, "git_revision", git_revision(), path);
  write_text_attr(meta_, "spec", meta.spec_text, path);
  write_text_attr(meta_, "spec_path", meta.spec_path, path);
  write_text_attr(meta_, "spec_name", meta.spec_name, path);
  write_text_attr(meta_, "created", utc_now(), path);
  write_text_attr(meta_, "host", host_name(), path);
  write_text_attr(meta_, "status", "incomplete", path);
  for (const auto& [k, v] : meta.text) write_text_attr(meta_, k, v, path);
  const hid_t mat = check_id(H5Gcreate2(meta_, "material", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
                             "creating /meta/material", path);
  for (const auto& [k, v] : meta.material) write_number_attr(mat, k, v, path);
  H5Gclose(mat);

  for (const auto& col : columns_) {
    const hsize_t dims[1] = {0}, maxdims[1] = {H5S_UNLIMITED}, chunk[1] = {512};
    const hid_t space = H5Screate_simple(1, dims, maxdims);
    const hid_t props = H5Pcreate(H5P_DATASET_CREATE);
    H5Pset_chunk(props, 1, chunk);
    const hid_t ds = H5Dcreate2(series_, col.name.c_str(), H5T_IEEE_F64LE, space, H5P_DEFAULT, props, H5P_DEFAULT);
    H5Pclose(props);
    H5Sclose(space);
    check_id(ds, "creating /series/" + col.name, path);
    datasets_.push_back(ds);
    write_text_attr(ds, "units", col.units, path);
  }
  csv_.open(tmp_csv_path_, std::ios::trunc);
  if (!csv_) throw WriteError(csv_path_ + ": cannot write the CSV copy");
  for (size_t c = 0; c < columns_.size(); ++c) csv_ << (c ? "," : "") << columns_[c].name;
  csv_ << '\n' << std::setprecision(10);
  flush();
}

ResultsWriter::~ResultsWriter() {
  // Left without finish() or fail(): an error ended the run. Keep what was
  // written, marked failed (or nothing, if even that cannot be written).
  if (open_) fail("the run stopped before it finished (an error; see the program's message)");
}

void ResultsWriter::close_handles() {
  for (hid_t d : datasets_) H5Dclose(d);
  datasets_.clear();
  for (auto& [name, set] : sets_) {
    if (set.time >= 0) H5Dclose(set.time);
    if (set.displacement >= 0) H5Dclose(set.displacement);
    set.time = set.displacement = -1;
  }
  for (hid_t* g : {&fields_, &metrics_, &timing_, &series_, &meta_})
    if (*g >= 0) {
      H5Gclose(*g);
      *g = -1;
    }
  if (csv_.is_open()) csv_.close();
}

void ResultsWriter::discard() {
  if (file_ >= 0) {
    // The file is thrown away, but HDF5 flushes its cached metadata when it
    // closes; on a full disk that fails, the file stays half-closed and HDF5
    // crashes when it shuts down. Point its descriptor at /dev/null so most
    // of the close succeeds; if the close still fails (it truncates the file
    // to its end, which /dev/null refuses), hdf5_damaged() tells the program
    // to end without shutting HDF5 down.
    void* handle = nullptr;
    const hid_t fapl = H5Fget_access_plist(file_);
    if (fapl >= 0 && H5Fget_vfd_handle(file_, fapl, &handle) >= 0 && handle) {
      const int null_fd = ::open("/dev/null", O_WRONLY | O_CLOEXEC);
      if (null_fd >= 0) {
        ::dup2(null_fd, *static_cast<int*>(handle));
        ::close(null_fd);
      }
    }
    if (fapl >= 0) H5Pclose(fapl);
  }
  close_handles();
  if (file_ >= 0 && H5Fclose(file_) < 0) g_hdf5_damaged = true;
  file_ = -1;
  open_ = false;
  std::error_code ignore;
  std::filesystem::remove(tmp_path_, ignore);
  std::filesystem::remove(tmp_csv_path_, ignore);
  tmp_registered_.reset();
  csv_registered_.reset();
  lock_.reset();
}

void ResultsWriter::commit() {
  // Everything reaches the disk while the file is open (a failure here is
  // recoverable: discard()), then the close has nothing left to write.
  const herr_t flushed = H5Fflush(file_, H5F_SCOPE_GLOBAL);
  if (csv_.is_open()) csv_.close();
  if (flushed < 0 || csv_.fail()) {
    discard();
    throw WriteError((flushed < 0 ? path_ : csv_path_) + ": write failed while closing (disk full or file size limit?)");
  }
  close_handles();
  const herr_t closed = H5Fclose(file_);
  file_ = -1;
  if (closed < 0) {
    discard();
    throw WriteError(path_ + ": write failed while closing (disk full or file size limit?)");
  }
  try {
    msd::commit_partial(tmp_csv_path_, csv_path_);
    msd::commit_partial(tmp_path_, path_);
  } catch (const msd::Error& e) {
    discard();
    throw WriteError(e.what());
  }
  open_ = false;
  tmp_registered_.reset();
  csv_registered_.reset();
  lock_.reset();
}

void ResultsWriter::append(const std::vector<double>& row) {
  if (row.size() != columns_.size())
    throw msd::Error(path_ + ": a row of " + std::to_string(row.size()) + " values for " +
                     std::to_string(columns_.size()) + " series");
  for (size_t c = 0; c < row.size(); ++c) {
    pending_[c].push_back(row[c]);
    csv_ << (c ? "," : "") << row[c];
  }
  csv_ << '\n';
  ++rows_;
  if (std::chrono::steady_clock::now() - last_flush_ > std::chrono::milliseconds(500)) flush();
}

void ResultsWriter::flush() {
  if (!open_) throw WriteError(path_ + ": written to after it was closed");
  const size_t n = pending_.empty() ? 0 : pending_.front().size();
  if (n > 0) {
    const hsize_t old_rows = static_cast<hsize_t>(rows_) - n;
    for (size_t c = 0; c < columns_.size(); ++c) {
      const hsize_t new_size[1] = {static_cast<hsize_t>(rows_)};
      check(H5Dset_extent(datasets_[c], new_size), "extending /series/" + columns_[c].name, path_);
      const hid_t fspace = H5Dget_space(datasets_[c]);
      const hsize_t start[1] = {old_rows}, count[1] = {n};
      H5Sselect_hyperslab(fspace, H5S_SELECT_SET, start, nullptr, count, nullptr);
      const hid_t mspace = H5Screate_simple(1, count, nullptr);
      const herr_t w = H5Dwrite(datasets_[c], H5T_NATIVE_DOUBLE, mspace, fspace, H5P_DEFAULT, pending_[c].data());
      H5Sclose(mspace);
      H5Sclose(fspace);
      check(w, "writing /series/" + columns_[c].name, path_);
    }
    for (auto& p : pending_) p.clear();
  }
  check(H5Fflush(file_, H5F_SCOPE_GLOBAL), "flushing", path_);
  csv_.flush();
  if (!csv_) throw WriteError(csv_path_ + ": write failed (disk full or file size limit?)");
  last_flush_ = std::chrono::steady_clock::now();
}

void ResultsWriter::set_timing(double wall_seconds, long steps, double dt, int threads) {
  write_number_attr(timing_, "wall_seconds", wall_seconds, path_);
  write_number_attr(timing_, "steps", static_cast<double>(steps), path_);
  write_number_attr(timing_, "dt", dt, path_);
  write_number_attr(timing_, "threads", threads, path_);
}

void ResultsWriter::set_timing_detail(const std::string& key, double value) {
  write_number_attr(timing_, key, value, path_);
}

void ResultsWriter::set_metric(const std::string& key, double value) {
  write_number_attr(metrics_, key, value, path_);
}

void ResultsWriter::add_point_set(const std::string& name, const std::vector<std::array<double, 3>>& points,
                                  const std::vector<std::vector<int>>& cells) {
  if (sets_.count(name)) throw msd::Error(path_ + ": /fields point set '" + name + "' written twice");
  if (fields_ < 0)
    fields_ = check_id(H5Gcreate2(file_, "fields", H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), "creating /fields", path_);
  PointSet set;
  set.points = static_cast<long>(points.size());
  auto write2d = [&](const std::string& ds_name, hid_t type, hid_t mem, const void* data, hsize_t rows,
                     hsize_t width) {
    const hsize_t dims[2] = {rows, width};
    const hid_t space = H5Screate_simple(2, dims, nullptr);
    const hid_t ds = check_id(
        H5Dcreate2(fields_, ds_name.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
        "creating /fields/" + ds_name, path_);
    if (rows > 0) check(H5Dwrite(ds, mem, H5S_ALL, H5S_ALL, H5P_DEFAULT, data), "writing /fields", path_);
    H5Dclose(ds);
    H5Sclose(space);
  };
  write2d(name + "_points", H5T_IEEE_F64LE, H5T_NATIVE_DOUBLE, points.data(), points.size(), 3);
  if (!cells.empty()) {
    const size_t width = cells.front().size();
    std::vector<int> flat;
    for (const auto& c : cells) {
      if (c.size() != width) throw msd::Error(path_ + ": cells of mixed sizes in /fields/" + name);
      flat.insert(flat.end(), c.begin(), c.end());
    }
    write2d(name + (width == 3 ? "_triangles" : "_tets"), H5T_STD_I32LE, H5T_NATIVE_INT, flat.data(), cells.size(),
            width);
  }
  const hsize_t d1[1] = {0}, m1[1] = {H5S_UNLIMITED}, c1[1] = {64};
  const hsize_t n = static_cast<hsize_t>(points.size());
  const hsize_t d3[3] = {0, n, 3}, m3[3] = {H5S_UNLIMITED, n, 3}, c3[3] = {1, std::max<hsize_t>(1, n), 3};
  hid_t space = H5Screate_simple(1, d1, m1), props = H5Pcreate(H5P_DATASET_CREATE);
  H5Pset_chunk(props, 1, c1);
  set.time = check_id(H5Dcreate2(fields_, (name + "_time").c_str(), H5T_IEEE_F64LE, space, H5P_DEFAULT, props,
                                 H5P_DEFAULT),
                      "creating /fields/" + name + "_time", path_);
  H5Pclose(props);
  H5Sclose(space);
  space = H5Screate_simple(3, d3, m3);
  props = H5Pcreate(H5P_DATASET_CREATE);
  H5Pset_chunk(props, 3, c3);
  set.displacement = check_id(H5Dcreate2(fields_, (name + "_displacement").c_str(), H5T_IEEE_F64LE, space,
                                         H5P_DEFAULT, props, H5P_DEFAULT),
                              "creating /fields/" + name + "_displacement", path_);
  write_text_attr(set.displacement, "units", "m", path_);
  H5Pclose(props);
  H5Sclose(space);
  sets_[name] = set;
}

void ResultsWriter::append_frame(const std::string& name, double time,
                                 const std::vector<std::array<double, 3>>& displacement) {
  const auto it = sets_.find(name);
  if (it == sets_.end()) throw msd::Error(path_ + ": append_frame before add_point_set('" + name + "')");
  PointSet& set = it->second;
  if (static_cast<long>(displacement.size()) != set.points)
    throw msd::Error(path_ + ": a frame of " + std::to_string(displacement.size()) + " displacements for " +
                     std::to_string(set.points) + " points in /fields/" + name);
  const hsize_t f = static_cast<hsize_t>(set.frames);
  const hsize_t n1[1] = {f + 1};
  check(H5Dset_extent(set.time, n1), "extending /fields/" + name + "_time", path_);
  hid_t fs = H5Dget_space(set.time);
  const hsize_t s1[1] = {f}, k1[1] = {1};
  H5Sselect_hyperslab(fs, H5S_SELECT_SET, s1, nullptr, k1, nullptr);
  hid_t ms = H5Screate_simple(1, k1, nullptr);
  check(H5Dwrite(set.time, H5T_NATIVE_DOUBLE, ms, fs, H5P_DEFAULT, &time), "writing a frame time", path_);
  H5Sclose(ms);
  H5Sclose(fs);
  const hsize_t n = static_cast<hsize_t>(set.points);
  const hsize_t n3[3] = {f + 1, n, 3};
  check(H5Dset_extent(set.displacement, n3), "extending /fields/" + name + "_displacement", path_);
  fs = H5Dget_space(set.displacement);
  const hsize_t s3[3] = {f, 0, 0}, k3[3] = {1, n, 3};
  H5Sselect_hyperslab(fs, H5S_SELECT_SET, s3, nullptr, k3, nullptr);
  ms = H5Screate_simple(3, k3, nullptr);
  if (n > 0)
    check(H5Dwrite(set.displacement, H5T_NATIVE_DOUBLE, ms, fs, H5P_DEFAULT, displacement.data()),
          "writing a frame", path_);
  H5Sclose(ms);
  H5Sclose(fs);
  ++set.frames;
}

void ResultsWriter::set_meta(const std::string& key, const std::string& value) {
  write_text_attr(meta_, key, value, path_);
}

void ResultsWriter::finish() {
  try {
    flush();
    write_text_attr(meta_, "status", "complete", path_);
  } catch (...) {
    discard();
    throw;
  }
  commit();
}

bool ResultsWriter::fail(const std::string& message) {
  if (!open_) return false;
  try {
    flush();
    write_text_attr(meta_, "failure", message, path_);
    write_text_attr(meta_, "status", "failed", path_);
    commit();
    return true;
  } catch (const std::exception&) {
    if (open_) discard();
    return false;
  }
}

ResultsSnapshot ResultsWriter::snapshot() {
  flush();
  ResultsSnapshot s;
  s.rows.assign(static_cast<size_t>(rows_), std::vector<double>(columns_.size()));
  std::vector<double> column(static_cast<size_t>(rows_));
  for (size_t c = 0; c < columns_.size(); ++c) {
    if (rows_ > 0)
      check(H5Dread(datasets_[c], H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, column.data()),
            "reading /series/" + columns_[c].name + " back", path_);
    for (size_t r = 0; r < column.size(); ++r) s.rows[r][c] = column[r];
  }
  for (const auto& [name, set] : sets_) {
    ResultsSnapshot::Frames& f = s.fields[name];
    f.time.resize(static_cast<size_t>(set.frames));
    f.displacement.assign(static_cast<size_t>(set.frames),
                          std::vector<std::array<double, 3>>(static_cast<size_t>(set.points)));
    if (set.frames == 0) continue;
    check(H5Dread(set.time, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, f.time.data()),
          "reading /fields/" + name + "_time back", path_);
    if (set.points == 0) continue;
    std::vector<double> all(static_cast<size_t>(set.frames * set.points * 3));
    check(H5Dread(set.displacement, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, all.data()),
          "reading /fields/" + name + "_displacement back", path_);
    for (size_t k = 0; k < all.size(); ++k)
      f.displacement[k / static_cast<size_t>(3 * set.points)][(k / 3) % static_cast<size_t>(set.points)][k % 3] =
          all[k];
  }
  return s;
}

void ResultsWriter::restore(const ResultsSnapshot& s) {
  for (const auto& row : s.rows) append(row);
  for (const auto& [name, f] : s.fields)
    for (size_t k = 0; k < f.time.size(); ++k) append_frame(name, f.time[k], f.displacement[k]);
  flush();
}

bool hdf5_damaged() { return g_hdf5_damaged; }

int end_program(int rc) {
  if (!g_hdf5_damaged) return rc;
  std::fflush(stdout);
  std::fflush(stderr);
  std::_Exit(rc);
}

std::string Results::status() const {
  const auto it = meta.find("status");
  return it == meta.end() ? "" : it->second;
}

namespace {

struct ReadCtx {
  Results* out;
  std::string path;
  hid_t group;
};

std::string read_text_attr(hid_t attr) {
  const hid_t ftype = H5Aget_type(attr);
  std::string value;
  if (H5Tis_variable_str(ftype) > 0) {
    const hid_t mtype = string_type();
    char* c = nullptr;
    if (H5Aread(attr, mtype, &c) >= 0 && c) {
      value = c;
      H5free_memory(c);
    }
    H5Tclose(mtype);
  } else {
    const size_t n = H5Tget_size(ftype);
    std::string buf(n, '\0');
    const hid_t mtype = H5Tcopy(H5T_C_S1);
    H5Tset_size(mtype, n);
    if (H5Aread(attr, mtype, buf.data()) >= 0) value = buf.c_str();
    H5Tclose(mtype);
  }
  H5Tclose(ftype);
  return value;
}

herr_t collect_attr(hid_t loc, const char* name, const H5A_info_t*, void* data) {
  auto* sink = static_cast<std::pair<std::map<std::string, std::string>*, std::map<std::string, double>*>*>(data);
  const hid_t attr = H5Aopen(loc, name, H5P_DEFAULT);
  if (attr < 0) return -1;
  const hid_t type = H5Aget_type(attr);
  const H5T_class_t cls = H5Tget_class(type);
  H5Tclose(type);
  if (cls == H5T_STRING && sink->first) {
    (*sink->first)[name] = read_text_attr(attr);
  } else if (cls == H5T_FLOAT && sink->second) {
    double v = 0.0;
    H5Aread(attr, H5T_NATIVE_DOUBLE, &v);
    (*sink->second)[name] = v;
  }
  H5Aclose(attr);
  return 0;
}

herr_t collect_dataset(hid_t group, const char* name, const H5L_info_t*, void* data) {
  auto* ctx = static_cast<ReadCtx*>(data);
  const hid_t ds = H5Dopen2(group, name, H5P_DEFAULT);
  if (ds < 0) return -1;
  const hid_t space = H5Dget_space(ds);
  hsize_t n = 0;
  if (H5Sget_simple_extent_ndims(space) != 1) {
    H5Sclose(space);
    H5Dclose(ds);
    return -1;
  }
  H5Sget_simple_extent_dims(space, &n, nullptr);
  std::vector<double> v(n);
  if (n > 0) H5Dread(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data());
  ctx->out->series[name] = std::move(v);
  if (H5Aexists(ds, "units") > 0) {
    const hid_t attr = H5Aopen(ds, "units", H5P_DEFAULT);
    ctx->out->units[name] = read_text_attr(attr);
    H5Aclose(attr);
  }
  H5Sclose(space);
  H5Dclose(ds);
  return 0;
}

}  // namespace

Results read_results(const std::string& path) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  if (!std::filesystem::exists(path)) throw msd::Error(path + ": results file does not exist");
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (file < 0) throw msd::Error(path + ": not a readable HDF5 file");
  Results r;
  auto open_group = [&](const char* name) {
    const hid_t g = H5Gopen2(file, name, H5P_DEFAULT);
    if (g < 0) {
      H5Fclose(file);
      throw msd::Error(path + ": missing group /" + std::string(name) + " (not a tissuebench results file)");
    }
    return g;
  };
  const hid_t meta = open_group("meta");
  std::pair<std::map<std::string, std::string>*, std::map<std::string, double>*> meta_sink{&r.meta, nullptr};
  H5Aiterate2(meta, H5_INDEX_NAME, H5_ITER_INC, nullptr, collect_attr, &meta_sink);
  if (H5Lexists(meta, "material", H5P_DEFAULT) > 0) {
    const hid_t mat = H5Gopen2(meta, "material", H5P_DEFAULT);
    std::pair<std::map<std::string, std::string>*, std::map<std::string, double>*> sink{nullptr, &r.material};
    H5Aiterate2(mat, H5_INDEX_NAME, H5_ITER_INC, nullptr, collect_attr, &sink);
    H5Gclose(mat);
  }
  H5Gclose(meta);
  const hid_t series = open_group("series");
  ReadCtx ctx{&r, path, series};
  const herr_t ok = H5Literate(series, H5_INDEX_NAME, H5_ITER_INC, nullptr, collect_dataset, &ctx);
  H5Gclose(series);
  const hid_t timing = open_group("timing");
  std::pair<std::map<std::string, std::string>*, std::map<std::string, double>*> tsink{nullptr, &r.timing};
  H5Aiterate2(timing, H5_INDEX_NAME, H5_ITER_INC, nullptr, collect_attr, &tsink);
  H5Gclose(timing);
  if (H5Lexists(file, "metrics", H5P_DEFAULT) > 0) {
    const hid_t g = H5Gopen2(file, "metrics", H5P_DEFAULT);
    std::pair<std::map<std::string, std::string>*, std::map<std::string, double>*> msink{nullptr, &r.metrics};
    H5Aiterate2(g, H5_INDEX_NAME, H5_ITER_INC, nullptr, collect_attr, &msink);
    H5Gclose(g);
  }
  if (H5Lexists(file, "fields", H5P_DEFAULT) > 0) {
    const hid_t g = H5Gopen2(file, "fields", H5P_DEFAULT);
    hsize_t count = 0;
    H5Gget_num_objs(g, &count);
    for (hsize_t i = 0; i < count; ++i) {
      char buf[256] = {0};
      H5Gget_objname_by_idx(g, i, buf, sizeof buf - 1);
      const std::string n(buf);
      const std::string suffix = "_displacement";
      if (n.size() <= suffix.size() || n.compare(n.size() - suffix.size(), suffix.size(), suffix) != 0) continue;
      const hid_t ds = H5Dopen2(g, n.c_str(), H5P_DEFAULT);
      const hid_t sp = H5Dget_space(ds);
      hsize_t dims[3] = {0, 0, 0};
      H5Sget_simple_extent_dims(sp, dims, nullptr);
      r.point_sets[n.substr(0, n.size() - suffix.size())] = {static_cast<long>(dims[1]), static_cast<long>(dims[0])};
      H5Sclose(sp);
      H5Dclose(ds);
    }
    H5Gclose(g);
  }
  H5Fclose(file);
  if (ok < 0) throw msd::Error(path + ": /series holds something other than 1-D datasets");
  size_t len = 0;
  bool first = true;
  for (const auto& [name, v] : r.series) {
    if (first) len = v.size();
    else if (v.size() != len)
      throw msd::Error(path + ": /series/" + name + " has " + std::to_string(v.size()) +
                       " values, others " + std::to_string(len));
    first = false;
  }
  return r;
}

PointSetData read_point_set(const std::string& path, const std::string& name) {
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  const hid_t file = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (file < 0) throw msd::Error(path + ": not a readable HDF5 file");
  PointSetData d;
  auto read = [&](const std::string& ds_name, std::vector<double>& out, std::vector<hsize_t>& dims) {
    const std::string full = "fields/" + ds_name;
    if (H5Lexists(file, "fields", H5P_DEFAULT) <= 0 || H5Lexists(file, full.c_str(), H5P_DEFAULT) <= 0) {
      H5Fclose(file);
      throw msd::Error(path + ": no /" + full + " (the run wrote no '" + name + "' fields)");
    }
    const hid_t ds = H5Dopen2(file, full.c_str(), H5P_DEFAULT);
    const hid_t sp = H5Dget_space(ds);
    const int rank = H5Sget_simple_extent_ndims(sp);
    dims.assign(static_cast<size_t>(rank), 0);
    H5Sget_simple_extent_dims(sp, dims.data(), nullptr);
    hsize_t total = 1;
    for (hsize_t x : dims) total *= x;
    out.assign(total, 0.0);
    if (total > 0) H5Dread(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data());
    H5Sclose(sp);
    H5Dclose(ds);
  };
  std::vector<double> buf;
  std::vector<hsize_t> dims;
  read(name + "_points", buf, dims);
  for (size_t i = 0; i + 2 < buf.size(); i += 3) d.points.push_back({{buf[i], buf[i + 1], buf[i + 2]}});
  const std::string tri_name = "fields/" + name + "_triangles";
  if (H5Lexists(file, tri_name.c_str(), H5P_DEFAULT) > 0) {
    read(name + "_triangles", buf, dims);
    for (size_t i = 0; i + 2 < buf.size(); i += 3)
      d.triangles.push_back({{static_cast<int>(buf[i]), static_cast<int>(buf[i + 1]), static_cast<int>(buf[i + 2])}});
  }
  read(name + "_time", d.time, dims);
  read(name + "_displacement", buf, dims);
  const size_t n = d.points.size();
  if (n > 0) d.time.resize(std::min(d.time.size(), buf.size() / (3 * n)));
  for (size_t f = 0; f < d.time.size(); ++f) {
    std::vector<std::array<double, 3>> frame(n);
    for (size_t i = 0; i < n; ++i)
      for (int c = 0; c < 3; ++c) frame[i][static_cast<size_t>(c)] = buf[(f * n + i) * 3 + static_cast<size_t>(c)];
    d.displacement.push_back(std::move(frame));
  }
  H5Fclose(file);
  return d;
}

}  // namespace tbio
