#include "service/height_datum.hpp"

#include <cmath>
#include <utility>

#include <proj.h>

#include "planning/core/enum_names.hpp"

namespace skyroute {

namespace {

constexpr const char* kGridName = "egm96_15.gtx";
constexpr const char* kAmslCrs = "EPSG:4326+5773";     // WGS 84 latitude, longitude + EGM96 height
constexpr const char* kEllipsoidCrs = "EPSG:4979";      // WGS 84 latitude, longitude, ellipsoidal height

std::string joined(const std::vector<std::string>& parts) {
  std::string out;
  for (const auto& p : parts) out += (out.empty() ? "" : ", ") + p;
  return out;
}

// The folders PROJ searches by default, for the missing-grid message.
std::string defaultSearchPath() {
  const char* path = proj_info().searchpath;
  return path != nullptr && *path != '\0' ? path : "PROJ's built-in data folder";
}

Error projError(PJ_CONTEXT* ctx, const std::string& what) {
  const int code = proj_context_errno(ctx);
  const char* text = code != 0 ? proj_context_errno_string(ctx, code) : nullptr;
  return make_error(ErrorCode::kInternal, "PROJ", what + (text != nullptr ? std::string(" (") + text + ")" : ""));
}

Status checkLatLon(double lat_deg, double lon_deg, const std::string& field) {
  if (!std::isfinite(lat_deg) || std::abs(lat_deg) > 90.0)
    return make_error(ErrorCode::kInvalidArgument, field + ".lat_deg",
                      "latitude " + std::to_string(lat_deg) + " is not within -90..90 degrees");
  if (!std::isfinite(lon_deg) || std::abs(lon_deg) > 180.0)
    return make_error(ErrorCode::kInvalidArgument, field + ".lon_deg",
                      "longitude " + std::to_string(lon_deg) + " is not within -180..180 degrees");
  return Status::success();
}

}  // namespace

constexpr EnumName<HeightReference> kHeightReferenceNames[] = {{HeightReference::kAmsl, "amsl"},
                                                                {HeightReference::kEllipsoid, "ellipsoid"}};

std::string_view to_string(HeightReference reference) { return enumName(kHeightReferenceNames, reference, "amsl"); }

std::optional<HeightReference> parseHeightReference(std::string_view text) {
  return enumNamed(kHeightReferenceNames, text);
}

struct Egm96Geoid::Impl {
  PJ_CONTEXT* ctx = nullptr;
  PJ* op = nullptr;  // EGM96 heights -> ellipsoidal heights; PJ_INV goes back
  std::string operation_name;
  std::string grid_path;

  Impl() = default;
  Impl(const Impl&) = delete;
  Impl& operator=(const Impl&) = delete;
  ~Impl() {
    if (op != nullptr) proj_destroy(op);
    if (ctx != nullptr) proj_context_destroy(ctx);
  }

  // Converts height in place, in the direction given; the coordinate order is the CRSs' (lat, lon).
  Status transform(double lat_deg, double lon_deg, double& height_m, PJ_DIRECTION direction,
                   const std::string& field) const {
    if (Status ok = checkLatLon(lat_deg, lon_deg, field); !ok) return ok;
    if (!std::isfinite(height_m))
      return make_error(ErrorCode::kInvalidArgument, field + ".height_m", "the height is not a finite number");
    proj_errno_reset(op);
    const PJ_COORD out = proj_trans(op, direction, proj_coord(lat_deg, lon_deg, height_m, 0.0));
    const int code = proj_errno(op);
    if (code != 0 || !std::isfinite(out.xyz.z) || out.xyz.z == HUGE_VAL) {
      const char* text = code != 0 ? proj_context_errno_string(ctx, code) : "no result";
      return make_error(ErrorCode::kInternal, field,
                        "PROJ could not convert the height at " + std::to_string(lat_deg) + ", " +
                            std::to_string(lon_deg) + " with " + grid_path + " (" + text + ")");
    }
    height_m = out.xyz.z;
    return Status::success();
  }
};

Egm96Geoid::Egm96Geoid(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
Egm96Geoid::Egm96Geoid(Egm96Geoid&&) noexcept = default;
Egm96Geoid& Egm96Geoid::operator=(Egm96Geoid&&) noexcept = default;
Egm96Geoid::~Egm96Geoid() = default;

Result<Egm96Geoid> Egm96Geoid::load(const GeoidOptions& options) {
  auto impl = std::make_unique<Impl>();
  impl->ctx = proj_context_create();
  if (impl->ctx == nullptr) return make_error(ErrorCode::kInternal, "PROJ", "cannot create a PROJ context");
  PJ_CONTEXT* ctx = impl->ctx;
  // The grid comes from the local installation only: a download would make results depend on
  // the network, and a failed one would surface in the middle of an export.
  proj_context_set_enable_network(ctx, 0);

  std::string searched = defaultSearchPath();
  if (!options.grid_search_paths.empty()) {
    // Keep PROJ's database where PROJ found it, and look for grids only in the given folders.
    const char* db = proj_context_get_database_path(ctx);
    if (db == nullptr) return projError(ctx, "PROJ's database proj.db was not found");
    const std::string db_path = db;
    std::vector<const char*> paths;
    for (const auto& p : options.grid_search_paths) paths.push_back(p.c_str());
    proj_context_set_search_paths(ctx, static_cast<int>(paths.size()), paths.data());
    if (!proj_context_set_database_path(ctx, db_path.c_str(), nullptr, nullptr))
      return projError(ctx, "cannot open PROJ's database " + db_path);
    searched = joined(options.grid_search_paths);
  }

  PJ* source = proj_create(ctx, kAmslCrs);
  PJ* target = proj_create(ctx, kEllipsoidCrs);
  if (source == nullptr || target == nullptr) {
    proj_destroy(source);
    proj_destroy(target);
    return projError(ctx, std::string("cannot create ") + kAmslCrs + " or " + kEllipsoidCrs);
  }
  PJ_OPERATION_FACTORY_CONTEXT* factory = proj_create_operation_factory_context(ctx, nullptr);
  // Only operations whose grid is installed, and never the "ballpark" one, which treats the two
  // heights as equal (N = 0) when the grid is missing.
  proj_operation_factory_context_set_grid_availability_use(ctx, factory,
                                                           PROJ_GRID_AVAILABILITY_DISCARD_OPERATION_IF_MISSING_GRID);
  proj_operation_factory_context_set_allow_ballpark_transformations(ctx, factory, 0);
  PJ_OBJ_LIST* operations = proj_create_operations(ctx, source, target, factory);
  proj_operation_factory_context_destroy(factory);
  proj_destroy(source);
  proj_destroy(target);
  const int count = operations != nullptr ? proj_list_get_count(operations) : 0;
  for (int i = 0; i < count && impl->op == nullptr; ++i) {
    PJ* op = proj_list_get(ctx, operations, i);
    if (op != nullptr && proj_coordoperation_is_instantiable(ctx, op)) {
      impl->op = op;
    } else {
      proj_destroy(op);
    }
  }
  proj_list_destroy(operations);
  if (impl->op == nullptr) {
    return make_error(ErrorCode::kFileNotFound, kGridName,
                      std::string("the EGM96 geoid grid ") + kGridName +
                          " (Debian package proj-data) was not found in " + searched +
                          ": heights cannot be converted between AMSL and the WGS 84 ellipsoid");
  }

  const char* name = proj_get_name(impl->op);
  impl->operation_name = name != nullptr ? name : "";
  for (int i = 0; i < proj_coordoperation_get_grid_used_count(ctx, impl->op); ++i) {
    const char* short_name = nullptr;
    const char* full_name = nullptr;
    if (proj_coordoperation_get_grid_used(ctx, impl->op, i, &short_name, &full_name, nullptr, nullptr, nullptr,
                                          nullptr, nullptr)) {
      impl->grid_path = full_name != nullptr && *full_name != '\0' ? full_name : (short_name ? short_name : "");
    }
  }
  return Egm96Geoid(std::move(impl));
}

const std::string& Egm96Geoid::operationName() const { return impl_->operation_name; }
const std::string& Egm96Geoid::gridPath() const { return impl_->grid_path; }

Result<double> Egm96Geoid::undulationM(double lat_deg, double lon_deg) const {
  return ellipsoidFromAmslM(lat_deg, lon_deg, 0.0);
}

Result<double> Egm96Geoid::ellipsoidFromAmslM(double lat_deg, double lon_deg, double alt_amsl_m) const {
  double h = alt_amsl_m;
  if (Status ok = impl_->transform(lat_deg, lon_deg, h, PJ_FWD, "point"); !ok) return ok.error();
  return h;
}

Result<double> Egm96Geoid::amslFromEllipsoidM(double lat_deg, double lon_deg, double alt_ellipsoid_m) const {
  double h = alt_ellipsoid_m;
  if (Status ok = impl_->transform(lat_deg, lon_deg, h, PJ_INV, "point"); !ok) return ok.error();
  return h;
}

Result<std::vector<double>> Egm96Geoid::ellipsoidHeightsM(const std::vector<GeoPoint>& points) const {
  std::vector<double> heights(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    heights[i] = points[i].alt_amsl_m;
    Status ok = impl_->transform(points[i].lat_deg, points[i].lon_deg, heights[i], PJ_FWD,
                                 "points[" + std::to_string(i) + "]");
    if (!ok) return ok.error();
  }
  return heights;
}

InputHeightConverter::InputHeightConverter(HeightReference reference, std::optional<Egm96Geoid> geoid)
    : reference_(reference), geoid_(std::move(geoid)) {}

Result<InputHeightConverter> InputHeightConverter::create(HeightReference reference, const GeoidOptions& options) {
  if (reference == HeightReference::kAmsl) return InputHeightConverter(reference, std::nullopt);
  auto geoid = Egm96Geoid::load(options);
  if (!geoid) return geoid.error();
  return InputHeightConverter(reference, std::move(*geoid));
}

Result<double> InputHeightConverter::toAmslM(double lat_deg, double lon_deg, double height_m,
                                             const std::string& field) const {
  if (Status ok = checkLatLon(lat_deg, lon_deg, field); !ok) return ok.error();
  if (!std::isfinite(height_m))
    return make_error(ErrorCode::kInvalidArgument, field, "the height is not a finite number");
  if (reference_ == HeightReference::kAmsl) return height_m;
  auto amsl = geoid_->amslFromEllipsoidM(lat_deg, lon_deg, height_m);
  if (!amsl) return make_error(amsl.error().code, field, amsl.error().message);
  return amsl;
}

}  // namespace skyroute
