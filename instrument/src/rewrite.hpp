// The body rewrite: walks the statement structure of every function, attaches the census
// of operations to basic blocks by position, and plans the text insertions that count them.
#pragma once

#include "ast_census.hpp"
#include "glbudget/instrument/instrument.hpp"
#include "syntax.hpp"

#include <string>
#include <string_view>
#include <vector>

namespace glbudget::instrument {

struct Insertion {
  std::size_t offset = 0;
  std::string text;
};

struct BodyPlan {
  std::vector<Insertion> insertions;  // in the order they must appear at equal offsets
  StaticFigures figures;
};

// Names the inserted code uses; declared by the header (header.hpp).
inline constexpr std::string_view kInstructionVariable = "glbudget_ins";
inline constexpr std::string_view kTexelVariable = "glbudget_tex";
inline constexpr std::string_view kFlushFunction = "glbudget_flush";

// Throws std::runtime_error when an operation cannot be placed in a block.
BodyPlan plan_body(std::string_view text, const syntax::Unit& unit, const std::vector<CountedNode>& nodes);

// Applies insertions (stable in their order at equal offsets).
std::string apply_insertions(std::string_view text, std::vector<Insertion> insertions);

}  // namespace glbudget::instrument
