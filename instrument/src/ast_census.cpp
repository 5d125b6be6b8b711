#include "ast_census.hpp"

#include <glslang/Public/ShaderLang.h>
#include <glslang/MachineIndependent/localintermediate.h>

namespace glbudget::instrument {

namespace {

using namespace glslang;

class Census : public TIntermTraverser {
 public:
  std::vector<CountedNode> nodes;

  bool visitUnary(TVisit, TIntermUnary* node) override {
    add(*node);
    return true;
  }

  bool visitBinary(TVisit, TIntermBinary* node) override {
    switch (node->getOp()) {
      case EOpIndexDirect:        // a[2]: addressing, free
      case EOpIndexDirectStruct:  // s.m
      case EOpVectorSwizzle:      // v.xy
      case EOpComma:
        break;
      default:
        add(*node);
    }
    return true;
  }

  bool visitAggregate(TVisit, TIntermAggregate* node) override {
    switch (node->getOp()) {
      case EOpNull:
      case EOpSequence:
      case EOpLinkerObjects:
      case EOpFunction:
      case EOpParameters:
      case EOpComma:
        break;
      default:  // built-in calls, constructors, user function calls
        add(*node);
    }
    return true;
  }

  bool visitSelection(TVisit, TIntermSelection* node) override {
    if (node->getBasicType() != EbtVoid) add(*node);  // ?: as a value (a select)
    return true;
  }

 private:
  void add(const TIntermOperator& node) {
    nodes.push_back({node.getLoc().line, node.getLoc().column, node.isSampling()});
  }
  void add(const TIntermSelection& node) { nodes.push_back({node.getLoc().line, node.getLoc().column, false}); }
};

}  // namespace

std::vector<CountedNode> census(TIntermNode& root) {
  Census census;
  root.traverse(&census);
  return std::move(census.nodes);
}

}  // namespace glbudget::instrument
