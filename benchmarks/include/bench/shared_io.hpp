// The shared file formats (io/, namespace tbio) the harness uses: strict YAML
// fields, the results file, series tools, ring-down analysis, SHA-256. Named
// here once so the harness's code reads them as its own vocabulary.
#pragma once

#include "tbio/results_file.hpp"
#include "tbio/series_tools.hpp"
#include "tbio/sha256.hpp"
#include "tbio/signal_analysis.hpp"
#include "tbio/yaml_fields.hpp"

namespace bench {

using tbio::Fields;
using tbio::load_yaml_file;

using tbio::PointSetData;
using tbio::read_point_set;
using tbio::read_results;
using tbio::Results;
using tbio::ResultsWriter;
using tbio::RunMeta;
using tbio::SeriesColumn;
using tbio::git_revision;
using tbio::tissuebench_version;

using tbio::interpolate;
using tbio::json_number;

using tbio::analyse_ring_down;
using tbio::analyse_ring_down_after;
using tbio::RingDown;

using tbio::sha256_hex;

}  // namespace bench
