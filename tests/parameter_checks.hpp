// Checks shared by the suites of declared parameters (tbio/parameter.hpp):
// each table well formed, and a docs page's field table the generated one.
#pragma once

#include "tbio/parameter.hpp"
#include "test_support.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <set>
#include <string>
#include <vector>

namespace testing_support {

/// Each path declared once, with a doc; a Number/Integer default inside its
/// range; a Choice default among its choices. Returns the number of paths.
inline size_t expect_well_declared(const std::vector<tbio::Parameter>& params) {
  std::set<std::string> seen;
  for (const tbio::Parameter& p : params) {
    SCOPED_TRACE(p.path);
    EXPECT_TRUE(seen.insert(p.path).second) << "declared twice";
    EXPECT_FALSE(p.doc.empty());
    if ((p.kind == tbio::Kind::Number || p.kind == tbio::Kind::Integer) && p.fallback) {
      EXPECT_TRUE(p.range.contains(*p.fallback)) << *p.fallback << " outside " << p.range.text();
    }
    if (p.kind == tbio::Kind::Choice && !p.default_text.empty()) {
      EXPECT_NE(std::find(p.choices.begin(), p.choices.end(), p.default_text), p.choices.end()) << p.default_text;
    }
  }
  return seen.size();
}

/// The table between "<!-- fields:begin (generated from SOURCE) -->" and
/// "<!-- fields:end -->" in the file at `doc_path` (relative to the source
/// tree) is markdown_table(params); when not, the generated table is written
/// to the build folder as `out_name` and the failure says where.
inline void expect_docs_table(const std::string& doc_path, const std::string& source,
                              const std::vector<tbio::Parameter>& params, const std::string& out_name) {
  const std::string doc = read_text(std::string(TISSUEBENCH_SOURCE_DIR) + "/" + doc_path);
  ASSERT_FALSE(doc.empty()) << doc_path << " cannot be read";
  const std::string begin = "<!-- fields:begin (generated from " + source + ") -->\n", end = "<!-- fields:end -->";
  const size_t a = doc.find(begin), b = doc.find(end);
  ASSERT_NE(a, std::string::npos) << doc_path << " has no field table markers for " << source;
  ASSERT_NE(b, std::string::npos) << doc_path << " has no " << end;
  const std::string expected = tbio::markdown_table(params);
  if (doc.substr(a + begin.size(), b - a - begin.size()) != expected) {
    const std::string out = std::string(TB_TEST_OUTPUT_DIR) + "/" + out_name;
    std::ofstream(out) << expected;
    ADD_FAILURE() << doc_path << "'s field table differs from the declarations in " << source
                  << "; the generated one is in " << out;
  }
}

}  // namespace testing_support
