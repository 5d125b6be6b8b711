// Operations and texel accesses in a glslang AST, by source position (counting rule in
// include/glbudget/instrument/instrument.hpp).
#pragma once

#include <vector>

class TIntermNode;  // glslang declares it outside its namespace

namespace glbudget::instrument {

struct CountedNode {
  int line = 0;               // glslang's 1-based line
  int column = 0;             // glslang's 1-based column
  bool texel_access = false;  // a sampling call (it is also one operation)
};

std::vector<CountedNode> census(TIntermNode& root);

}  // namespace glbudget::instrument
