#include "io/polyfem_expression.hpp"

#include <cctype>
#include <cmath>
#include <cstdlib>
#include <map>

namespace dipc {

// Recursive descent over
//   sum     := product (('+' | '-') product)*
//   product := unary (('*' | '/') unary)*
//   unary   := ('-' | '+') unary | power
//   power   := primary ('^' signed)?         (-2^2 = -(2^2), 2^-1 allowed)
//   signed  := ('-' | '+') signed | primary
//   primary := number | variable | pi | function '(' sum ')' | '(' sum ')'
class PolyfemExpressionParser {
 public:
  PolyfemExpressionParser(const std::string& text, PolyfemExpression& e) : text_(text), e_(e) {}

  int parse() {
    const int root = sum();
    skip_space();
    if (pos_ < text_.size()) fail(std::string("unexpected '") + text_[pos_] + "'");
    return root;
  }

 private:
  [[noreturn]] void fail(const std::string& what) const {
    throw std::invalid_argument("at character " + std::to_string(pos_ + 1) + ": " + what);
  }
  void skip_space() {
    while (pos_ < text_.size() && std::isspace(static_cast<unsigned char>(text_[pos_]))) ++pos_;
  }
  bool accept(char c) {
    skip_space();
    if (pos_ < text_.size() && text_[pos_] == c) {
      ++pos_;
      return true;
    }
    return false;
  }
  int add(PolyfemExpression::Node n) {
    e_.nodes_.push_back(n);
    return static_cast<int>(e_.nodes_.size()) - 1;
  }
  int binary(char op, int left, int right) {
    PolyfemExpression::Node n{op};
    n.left = left;
    n.right = right;
    return add(n);
  }
  int sum() {
    int left = product();
    for (;;) {
      if (accept('+'))
        left = binary('+', left, product());
      else if (accept('-'))
        left = binary('-', left, product());
      else
        return left;
    }
  }
  int product() {
    int left = unary();
    for (;;) {
      if (accept('*'))
        left = binary('*', left, unary());
      else if (accept('/'))
        left = binary('/', left, unary());
      else
        return left;
    }
  }
  int unary() {
    if (accept('-')) {
      PolyfemExpression::Node n{'~'};
      n.left = unary();
      return add(n);
    }
    if (accept('+')) return unary();
    return power();
  }
  int power() {
    const int base = primary();
    if (!accept('^')) return base;
    const int exponent = signed_primary();
    skip_space();
    if (pos_ < text_.size() && text_[pos_] == '^') fail("a^b^c is ambiguous; write a^(b^c) or (a^b)^c");
    return binary('^', base, exponent);
  }
  int signed_primary() {
    if (accept('-')) {
      PolyfemExpression::Node n{'~'};
      n.left = signed_primary();
      return add(n);
    }
    if (accept('+')) return signed_primary();
    return primary();
  }
  int primary() {
    skip_space();
    if (pos_ >= text_.size()) fail("expression ends where a value was expected");
    if (accept('(')) {
      const int inner = sum();
      if (!accept(')')) fail("expected ')'");
      return inner;
    }
    const char c = text_[pos_];
    if (std::isdigit(static_cast<unsigned char>(c)) || c == '.') {
      const char* begin = text_.c_str() + pos_;
      char* end = nullptr;
      const double v = std::strtod(begin, &end);
      if (end == begin) fail("malformed number");
      pos_ += static_cast<std::size_t>(end - begin);
      PolyfemExpression::Node n{'#'};
      n.value = v;
      return add(n);
    }
    if (!std::isalpha(static_cast<unsigned char>(c))) fail(std::string("unexpected '") + c + "'");
    const std::size_t start = pos_;
    while (pos_ < text_.size() && (std::isalnum(static_cast<unsigned char>(text_[pos_])) || text_[pos_] == '_')) ++pos_;
    const std::string name = text_.substr(start, pos_ - start);
    if (name == "x" || name == "y" || name == "z") {
      e_.uses_position_ = true;
      return add({name[0]});
    }
    if (name == "t") {
      e_.uses_time_ = true;
      return add({'t'});
    }
    if (name == "pi") {
      PolyfemExpression::Node n{'#'};
      n.value = M_PI;
      return add(n);
    }
    static const std::map<std::string, double (*)(double)> functions = {
        {"sin", [](double a) { return std::sin(a); }},   {"cos", [](double a) { return std::cos(a); }},
        {"tan", [](double a) { return std::tan(a); }},   {"asin", [](double a) { return std::asin(a); }},
        {"acos", [](double a) { return std::acos(a); }}, {"atan", [](double a) { return std::atan(a); }},
        {"exp", [](double a) { return std::exp(a); }},   {"log", [](double a) { return std::log(a); }},
        {"sqrt", [](double a) { return std::sqrt(a); }}, {"abs", [](double a) { return std::abs(a); }}};
    const auto f = functions.find(name);
    if (f == functions.end()) {
      pos_ = start;
      fail("unknown name \"" + name +
           "\" (variables x y z t, constant pi, functions sin cos tan asin acos atan exp log sqrt abs)");
    }
    if (!accept('(')) fail("expected '(' after " + name);
    PolyfemExpression::Node n{'f'};
    n.function = f->second;
    n.left = sum();
    if (!accept(')')) fail("expected ')'");
    return add(n);
  }

  const std::string& text_;
  PolyfemExpression& e_;
  std::size_t pos_ = 0;
};

PolyfemExpression::PolyfemExpression(const std::string& text) {
  PolyfemExpressionParser parser(text, *this);
  root_ = parser.parse();
}

double PolyfemExpression::evaluate(double x, double y, double z, double t) const {
  // Nodes are stored after their operands, so one pass in storage order evaluates them all.
  std::vector<double> v(nodes_.size());
  for (std::size_t i = 0; i < nodes_.size(); ++i) {
    const Node& n = nodes_[i];
    const double a = n.left >= 0 ? v[n.left] : 0, b = n.right >= 0 ? v[n.right] : 0;
    switch (n.op) {
      case '#': v[i] = n.value; break;
      case 'x': v[i] = x; break;
      case 'y': v[i] = y; break;
      case 'z': v[i] = z; break;
      case 't': v[i] = t; break;
      case '+': v[i] = a + b; break;
      case '-': v[i] = a - b; break;
      case '*': v[i] = a * b; break;
      case '/': v[i] = a / b; break;
      case '^': v[i] = std::pow(a, b); break;
      case '~': v[i] = -a; break;
      case 'f': v[i] = n.function(a); break;
    }
  }
  return v[root_];
}

}  // namespace dipc
