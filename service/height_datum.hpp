// Heights above mean sea level (the EGM96 geoid: the datum of SRTM/NASADEM, of the service and of
// MAVLink's AMSL fields) and above the WGS 84 ellipsoid (GeoJSON, GNSS, PX4's alt_ellipsoid), and the
// conversion between them: h_ellipsoid = H_amsl + N, N being the geoid undulation at the point.
// The conversion goes through PROJ (EPSG:4326+5773 -> EPSG:4979) with the EGM96 grid that Debian's
// proj-data ships (egm96_15.gtx). Without the grid there is no conversion at all: PROJ's fallback
// ("ballpark") would keep the height unchanged, i.e. assume N = 0, which is wrong by up to 100 m.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "terrain/local_frame.hpp"
#include "planning/core/result.hpp"

namespace skyroute {

// Which surface a height given by a user or a file is measured from.
enum class HeightReference { kAmsl, kEllipsoid };

std::string_view to_string(HeightReference reference);  // "amsl", "ellipsoid"
// Accepts exactly the names to_string gives (the `--height-ref amsl|ellipsoid` option).
std::optional<HeightReference> parseHeightReference(std::string_view text);

// The datum names written into exported files, so a reader never has to guess.
inline constexpr const char* kAmslDatumName = "EGM96 geoid (AMSL, EPSG:5773)";
inline constexpr const char* kEllipsoidDatumName = "WGS 84 ellipsoid (EPSG:4979)";

struct GeoidOptions {
  // Folders to look for the EGM96 grid in, instead of PROJ's own search path (PROJ_DATA, then the
  // installation's share/proj). PROJ's database (proj.db) is still found the usual way.
  std::vector<std::string> grid_search_paths;
};

// The EGM96 geoid through PROJ. Not thread-safe (it owns a PROJ context): use one per thread.
class Egm96Geoid {
 public:
  // Error kFileNotFound (field "egm96_15.gtx") when PROJ finds no usable EGM96 grid, naming the
  // folders searched and the Debian package that ships it.
  static Result<Egm96Geoid> load(const GeoidOptions& options = {});

  Egm96Geoid(Egm96Geoid&&) noexcept;
  Egm96Geoid& operator=(Egm96Geoid&&) noexcept;
  ~Egm96Geoid();

  // N: the geoid's height above the WGS 84 ellipsoid at the point, metres.
  Result<double> undulationM(double lat_deg, double lon_deg) const;
  Result<double> ellipsoidFromAmslM(double lat_deg, double lon_deg, double alt_amsl_m) const;
  Result<double> amslFromEllipsoidM(double lat_deg, double lon_deg, double alt_ellipsoid_m) const;
  // One bulk conversion: the ellipsoidal height of each point (GeoPoint's altitude is AMSL).
  Result<std::vector<double>> ellipsoidHeightsM(const std::vector<GeoPoint>& points) const;

  // What PROJ uses, for logs and messages: the operation's name and the grid file's full path.
  const std::string& operationName() const;
  const std::string& gridPath() const;

 private:
  struct Impl;
  explicit Egm96Geoid(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

// Turns heights given in a chosen reference into AMSL, the service's own datum: what an input option
// such as `--height-ref amsl|ellipsoid` needs. It loads the grid only for ellipsoidal inputs, so AMSL
// inputs work without it, and it fails when created (before any work) if the grid is missing.
class InputHeightConverter {
 public:
  static Result<InputHeightConverter> create(HeightReference reference, const GeoidOptions& options = {});

  HeightReference reference() const { return reference_; }
  // field names the input in errors (e.g. "--from").
  Result<double> toAmslM(double lat_deg, double lon_deg, double height_m, const std::string& field) const;

 private:
  InputHeightConverter(HeightReference reference, std::optional<Egm96Geoid> geoid);
  HeightReference reference_;
  std::optional<Egm96Geoid> geoid_;
};

}  // namespace skyroute
