#include "truth/point_bytes.hpp"

namespace pldamp::harness {
namespace {

void put_exacts(ByteWriter& out, const std::vector<std::optional<Exact>>& values) {
  out.put<std::uint64_t>(values.size());
  for (const std::optional<Exact>& value : values) {
    out.put<std::uint8_t>(value ? 1 : 0);
    if (value) {
      put_real(out, *value);
    }
  }
}

std::vector<std::optional<Exact>> get_exacts(ByteReader& in) {
  std::vector<std::optional<Exact>> values(in.size());
  for (std::optional<Exact>& value : values) {
    const auto flag = in.get<std::uint8_t>();
    if (flag > 1) {
      in.corrupt();
    }
    if (flag == 1) {
      value = get_real<Exact>(in);
    }
  }
  return values;
}

bool get_flag(ByteReader& in) {
  const auto flag = in.get<std::uint8_t>();
  if (flag > 1) {
    in.corrupt();
  }
  return flag == 1;
}

} // namespace

// Every field of a Point, in declaration order: a field added to Point changes its size and stops
// the build here until it is written and read too.
// (Exact: float128, or 50 digits in a build without it.)
static_assert(sizeof(Point) == (sizeof(Exact) == 16 ? 256 : 400),
              "a new Point field: write and read it below");

void put_point(ByteWriter& out, const Point& point) {
  out.put(point.p);
  out.put<std::uint8_t>(static_cast<std::uint8_t>(point.damping.kind));
  out.put(point.damping.value);
  out.put(point.alpha_eff);
  put_real(out, point.alpha);
  out.put<std::uint8_t>(point.overdamped ? 1 : 0);
  put_real(out, point.log_duration);
  out.put<std::uint64_t>(point.reference.size());
  for (const auto& [at, values] : point.reference) {
    out.put(at.first);
    out.put<std::uint8_t>(static_cast<std::uint8_t>(at.second));
    put_exacts(out, values);
  }
  out.put<std::uint64_t>(point.analytic.size());
  for (const AnalyticCheck& check : point.analytic) {
    out.put(check.value);
    out.put(check.error);
    out.put<std::uint8_t>(check.representable ? 1 : 0);
    out.put(check.log_error);
  }
  out.put(point.analytic_seconds);
  out.put(point.beta);
  out.put<std::uint8_t>(point.solved ? 1 : 0);
  out.put(point.truth_error);
  out.put(point.no_truth);
  put_real(out, point.group);
}

Point get_point(ByteReader& in) {
  Point point{};
  point.p = in.get<double>();
  const auto kind = in.get<std::uint8_t>();
  if (kind > static_cast<std::uint8_t>(Damping::Kind::alpha_eff)) {
    in.corrupt();
  }
  point.damping = {static_cast<Damping::Kind>(kind), in.get<double>()};
  point.alpha_eff = in.get<double>();
  point.alpha = get_real<Exact>(in);
  point.overdamped = get_flag(in);
  point.log_duration = get_real<Exact>(in);
  for (std::size_t n = in.size(); n > 0; --n) {
    std::string precision = in.string();
    const auto end = in.get<std::uint8_t>();
    if (end > static_cast<std::uint8_t>(solvers::End::force)) {
      in.corrupt();
    }
    point.reference[{std::move(precision), static_cast<solvers::End>(end)}] = get_exacts(in);
  }
  point.analytic.resize(in.size());
  for (AnalyticCheck& check : point.analytic) {
    check.value = in.optional();
    check.error = in.optional();
    check.representable = get_flag(in);
    check.log_error = in.optional();
  }
  point.analytic_seconds = in.get<double>();
  point.beta = in.optional();
  point.solved = get_flag(in);
  point.truth_error = in.optionals();
  point.no_truth = in.string();
  point.group = get_real<Exact>(in);
  return point;
}

void append_points(std::string& bytes, std::span<const Point> points) {
  ByteWriter out(bytes);
  out.put<std::uint64_t>(points.size());
  for (const Point& point : points) {
    put_point(out, point);
  }
}

std::vector<Point> read_points(std::string_view bytes, const std::string& source) {
  ByteReader in(bytes, source);
  std::vector<Point> points(in.size());
  for (Point& point : points) {
    point = get_point(in);
  }
  if (!in.at_end()) {
    in.corrupt();
  }
  return points;
}

} // namespace pldamp::harness
