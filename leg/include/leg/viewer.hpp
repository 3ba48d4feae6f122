// The leg in the browser (viewer/README.md): the page, its run data for
// `tissuebench view RUN_DIR`, and the pieces `tissuebench serve` streams.
// The page's template and script bundle are compiled into the program
// (viewer/embed.cmake), so neither command needs a file at run time.
#pragma once

#include "tbio/json.hpp"

#include "msd/core/types.hpp"

#include <cstddef>
#include <string>
#include <vector>

namespace leg {

/// The viewer page with `config` inlined ({"mode": "run", "run": ...} or
/// {"mode": "live", "ws": "/ws"}): self-contained HTML.
std::string viewer_page(const tbio::Json& config);

/// Standard base64 (RFC 4648, with padding) of `bytes` bytes.
std::string base64(const void* data, size_t bytes);

/// A mesh of the page: name, colour, opacity, counts, triangles (uint32) and
/// rest positions (float32), both base64. `rest` is 3 x V.
tbio::Json viewer_mesh(const std::string& name, const msd::Points& rest, const std::vector<msd::Tri>& triangles);

/// Positions (3 x V) as base64 float32, x y z per vertex.
std::string positions_base64(const msd::Points& x);

struct ViewOptions {
  int max_frames = 240;  ///< at most this many frames (every k-th, and the last)
};

/// The run data of a leg run's folder (RUN_DIR/leg.h5): status and failure,
/// frame times, the skin and bone meshes with their displacements (int16,
/// scaled), the series. Throws msd::Error naming the folder when it holds no
/// leg.h5 (listing the variants' folders when it holds those instead) or the
/// file has no skin frames.
tbio::Json view_run_data(const std::string& run_dir, const ViewOptions& options = {});

}  // namespace leg
