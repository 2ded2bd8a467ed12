// The arithmetic expressions of x, y, z and t that PolyFEM's JSON takes wherever a value may
// vary (boundary and initial conditions, body force): numbers, the variables x y z t, the
// constant pi, + - * / ^, parentheses and the functions sin cos tan asin acos atan exp log
// sqrt abs. Written for dipc's PolyFEM reader (polyfem_scene.cpp), which needs a value's
// numbers and whether it depends on position; a^b^c is refused (its grouping differs between
// expression libraries).
#pragma once
#include <stdexcept>
#include <string>
#include <vector>

namespace dipc {

class PolyfemExpression {
 public:
  // Throws std::invalid_argument("at character N: ...") on a syntax error or unknown name.
  explicit PolyfemExpression(const std::string& text);

  double evaluate(double x, double y, double z, double t) const;
  bool uses_position() const { return uses_position_; }  // mentions x, y or z
  bool uses_time() const { return uses_time_; }

  struct Node {
    char op;           // '#' number, 'x' 'y' 'z' 't' variables, + - * / ^, '~' negation, 'f' function
    double value = 0;  // the number
    double (*function)(double) = nullptr;
    int left = -1, right = -1;  // operand nodes
  };

 private:
  std::vector<Node> nodes_;
  int root_ = -1;
  bool uses_position_ = false, uses_time_ = false;
  friend class PolyfemExpressionParser;
};

}  // namespace dipc
