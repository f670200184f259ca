// Bindings of the DVI front end (docs/frontend.md, issue 13): the image pipeline ImageFrontend
// (detection, KLT, long-baseline epipolar test of moving features) on NumPy images, and the
// epipolar classifier alone on matched pixels (classify_matches), as `slamkit frontend` and
// `slamkit vio --images` run them. Images are 2-D uint8 arrays (rows × columns, grayscale).
#include <algorithm>
#include <cstring>

#include "bind_common.h"
#include "slamkit/io/kalibr_calibration.h"
#include "slamkit/vio/frontend_io.h"
#include "slamkit/vio/image_frontend.h"

namespace slamkit::python {
namespace {

GrayImage to_gray(const py::handle& obj, const char* what) {
  if (!py::isinstance<py::array>(obj)) throw py::value_error(std::string(what) + ": expected a 2-D uint8 NumPy array");
  const auto a = py::reinterpret_borrow<py::array>(obj);
  if (a.ndim() != 2 || !a.dtype().is(py::dtype::of<std::uint8_t>()))
    throw py::value_error(std::string(what) + ": expected a 2-D uint8 array (rows, columns), got " +
                          std::to_string(a.ndim()) + "-D of dtype " + py::str(a.dtype()).cast<std::string>());
  if (a.shape(0) < 1 || a.shape(1) < 1) throw py::value_error(std::string(what) + ": empty image");
  const auto c = py::array_t<std::uint8_t, py::array::c_style | py::array::forcecast>::ensure(a);
  GrayImage image(static_cast<int>(c.shape(1)), static_cast<int>(c.shape(0)));
  std::memcpy(image.pixels.data(), c.data(), image.pixels.size());
  return image;
}

py::array_t<std::uint8_t> to_numpy(const GrayImage& image) {
  py::array_t<std::uint8_t> a({image.height, image.width});
  std::memcpy(a.mutable_data(), image.pixels.data(), image.pixels.size());
  return a;
}

std::vector<Eigen::Vector2d> to_pixels(const py::handle& obj, const char* what) {
  const RowMatrixXd m = to_rows(obj, 2, what);
  std::vector<Eigen::Vector2d> out(static_cast<std::size_t>(m.rows()));
  for (Eigen::Index i = 0; i < m.rows(); ++i) out[static_cast<std::size_t>(i)] = m.row(i).transpose();
  return out;
}

std::shared_ptr<const CameraModel> camera_from(const std::string& calib) {
  if (calib.empty()) return nullptr;
  return read_kalibr_camchain(calib).front().model;
}

/// One processed frame as NumPy arrays (one row per feature) and the frame's counts.
struct FrontendFrame {
  py::array_t<std::int64_t> ids;
  py::array_t<double> uv;
  py::array_t<std::int8_t> motion;  ///< 0 unknown, 1 static, 2 dynamic (FeatureMotion)
  py::array_t<int> baseline;
  py::array_t<bool> isolated;  ///< dynamic flags without a flagged neighbour (not counted in n_dynamic)
  py::array_t<bool> graced;    ///< flags kept through a test under the threshold (mover_grace_claims)
  double static_ratio = 1.0, tracking_ms = 0.0, classification_ms = 0.0;
  int n_static = 0, n_dynamic = 0, n_unknown = 0, tracked = 0, detected = 0;
  int n_realigned_affine = 0, n_unflagged_affine = 0, n_isolated = 0, n_contests_lost = 0, n_graced = 0;
  std::string status, motion_model;
  bool gyro_seeded = false, trust_undecided = false;
};

FrontendFrame to_frame(const FrontendFrameResult& r) {
  const auto n = static_cast<py::ssize_t>(r.features.size());
  FrontendFrame f;
  f.ids = py::array_t<std::int64_t>(n);
  f.uv = py::array_t<double>({n, py::ssize_t{2}});
  f.motion = py::array_t<std::int8_t>(n);
  f.baseline = py::array_t<int>(n);
  f.isolated = py::array_t<bool>(n);
  auto isolated = f.isolated.mutable_unchecked<1>();
  f.graced = py::array_t<bool>(n);
  auto graced = f.graced.mutable_unchecked<1>();
  auto ids = f.ids.mutable_unchecked<1>();
  auto uv = f.uv.mutable_unchecked<2>();
  auto motion = f.motion.mutable_unchecked<1>();
  auto baseline = f.baseline.mutable_unchecked<1>();
  for (py::ssize_t i = 0; i < n; ++i) {
    const FrontendFeature& ft = r.features[static_cast<std::size_t>(i)];
    ids(i) = ft.id, uv(i, 0) = ft.uv.x(), uv(i, 1) = ft.uv.y();
    motion(i) = static_cast<std::int8_t>(ft.motion), baseline(i) = ft.baseline, isolated(i) = ft.isolated;
    graced(i) = ft.graced;
  }
  f.static_ratio = r.static_ratio, f.tracking_ms = r.tracking_ms, f.classification_ms = r.classification_ms;
  f.n_static = r.n_static, f.n_dynamic = r.n_dynamic, f.n_unknown = r.n_unknown;
  f.tracked = r.tracking.tracked, f.detected = r.tracking.detected;
  f.status = to_string(r.status);
  f.motion_model = to_string(r.motion_model);
  f.gyro_seeded = r.tracking.gyro_seeded;
  f.n_realigned_affine = r.n_realigned_affine, f.n_unflagged_affine = r.n_unflagged_affine;
  f.n_isolated = r.n_isolated;
  f.n_contests_lost = r.n_contests_lost;
  f.trust_undecided = r.trust_undecided;
  f.n_graced = r.n_graced;
  return f;
}

// Flattened option fields: Python name → member of ImageFrontendOptions (tracker / filter / own).
template <class T>
void field(py::class_<ImageFrontendOptions>& c, const char* name, T FeatureTrackerOptions::*member, const char* doc) {
  c.def_property(
      name, [member](const ImageFrontendOptions& o) { return o.tracker.*member; },
      [member](ImageFrontendOptions& o, T v) { o.tracker.*member = v; }, doc);
}
template <class T>
void field(py::class_<ImageFrontendOptions>& c, const char* name, T DynamicFilterOptions::*member, const char* doc) {
  c.def_property(
      name, [member](const ImageFrontendOptions& o) { return o.filter.*member; },
      [member](ImageFrontendOptions& o, T v) { o.filter.*member = v; }, doc);
}

template <class T>
void field(py::class_<ImageFrontendOptions>& c, const char* name, T EpipolarSearchOptions::*member, const char* doc) {
  c.def_property(
      name, [member](const ImageFrontendOptions& o) { return o.epipolar_search.*member; },
      [member](ImageFrontendOptions& o, T v) { o.epipolar_search.*member = v; }, doc);
}

template <class T>
void field(py::class_<ImageFrontendOptions>& c, const char* name, T AffineRealignOptions::*member, const char* doc) {
  c.def_property(
      name, [member](const ImageFrontendOptions& o) { return o.affine_realign.*member; },
      [member](ImageFrontendOptions& o, T v) { o.affine_realign.*member = v; }, doc);
}

template <class T>
void field(py::class_<ImageFrontendOptions>& c, const char* name, T DynamicGroupOptions::*member, const char* doc) {
  c.def_property(
      name, [member](const ImageFrontendOptions& o) { return o.groups.*member; },
      [member](ImageFrontendOptions& o, T v) { o.groups.*member = v; }, doc);
}

// A tracker option that is an enum, exposed by its name (ValueError on an unknown one).
template <class E>
void named_field(py::class_<ImageFrontendOptions>& c, const char* name, E FeatureTrackerOptions::*member,
                 const char* (*to_name)(E), E (*parse)(const std::string&), const char* doc) {
  c.def_property(
      name, [member, to_name](const ImageFrontendOptions& o) { return std::string(to_name(o.tracker.*member)); },
      [member, parse](ImageFrontendOptions& o, const std::string& v) {
        try {
          o.tracker.*member = parse(v);
        } catch (const std::invalid_argument& e) {
          throw py::value_error(e.what());
        }
      },
      doc);
}

const std::vector<const char*> kOptionFields = {
    "max_features", "min_distance_px", "klt_window", "klt_pyramid_levels", "rlof_refine", "forward_backward_px", "ambiguity_px",
    "ambiguity_ratio", "threshold_px",
    "ransac_threshold_px", "static_camera_flow_px", "min_trusted_matches", "refine_essential", "known_rotation",
    "rotation_prior_sigma_rad", "pure_rotation_share", "cheirality", "gyro_klt", "baseline_frames",
    "consistency_checks", "consistency_hits", "trusted_model", "trusted_min_tests", "epipolar_search",
    "epipolar_search_range_px", "epipolar_search_ncc_drop", "epipolar_search_min_ncc", "affine_realign",
    "affine_min_correlation", "affine_refit_model", "group_min_support", "group_radius_factor", "group_turned_min_support",
    "group_turned_static_tests", "trust_contest_ratio", "trust_contest_frames", "young_trust_majority",
    "mover_grace_claims"};

ImageFrontendOptions options_from(const py::object& options, const py::kwargs& kw) {
  if (!options.is_none()) {
    if (kw.size() > 0) throw py::type_error("give options or keywords, not both");
    return options.cast<ImageFrontendOptions>();
  }
  py::object tmp = py::cast(ImageFrontendOptions{});
  set_from_kwargs(tmp, kw);
  return tmp.cast<ImageFrontendOptions>();
}

}  // namespace

void init_frontend(py::module_& m) {
  py::class_<ImageFrontendOptions> opt(m, "FrontendOptions",
                                       "Options of the DVI front end; every keyword defaults to the C++ default "
                                       "(`slamkit frontend` / `slamkit vio --images`).");
  opt.def(py::init([](const py::kwargs& kw) { return options_from(py::none(), kw); }));
  field(opt, "max_features", &FeatureTrackerOptions::max_features, "features kept per frame");
  field(opt, "min_distance_px", &FeatureTrackerOptions::min_distance_px, "minimum distance between features");
  field(opt, "klt_window", &FeatureTrackerOptions::klt_window, "KLT window side (px, >= 3)");
  field(opt, "klt_pyramid_levels", &FeatureTrackerOptions::klt_pyramid_levels, "KLT pyramid levels above the full image");
  named_field(opt, "rlof_refine", &FeatureTrackerOptions::rlof_refine, rlof_refine_name, parse_rlof_refine,
              "robust local optical flow (RLOF) refinement: 'off', 'track' (= 'on': the tracks) or 'test' (only the "
              "epipolar test's positions)");
  field(opt, "forward_backward_px", &FeatureTrackerOptions::forward_backward_px, "KLT forward-backward check");
  field(opt, "ambiguity_px", &FeatureTrackerOptions::ambiguity_px, "KLT ambiguity check distance (0: off)");
  field(opt, "ambiguity_ratio", &FeatureTrackerOptions::ambiguity_ratio, "KLT ambiguity residual ratio");
  field(opt, "threshold_px", &DynamicFilterOptions::threshold_px, "epipolar distance above which a feature moves");
  field(opt, "ransac_threshold_px", &DynamicFilterOptions::ransac_threshold_px, "RANSAC inlier distance");
  field(opt, "static_camera_flow_px", &DynamicFilterOptions::static_camera_flow_px,
        "median flow below which the camera counts as static");
  field(opt, "min_trusted_matches", &DynamicFilterOptions::min_trusted_matches,
        "trusted tracks needed to fit the camera's motion on them alone");
  field(opt, "refine_essential", &DynamicFilterOptions::refine_essential,
        "refine E on the bearings by robust least squares (fisheye calibration)");
  field(opt, "known_rotation", &DynamicFilterOptions::known_rotation,
        "IMU-aided test: with a rotation given to process(), fit only the translation (2-point RANSAC)");
  field(opt, "rotation_prior_sigma_rad", &DynamicFilterOptions::rotation_prior_sigma_rad,
        "known_rotation: sigma of the prior letting the refinement move R (0: R held)");
  field(opt, "pure_rotation_share", &DynamicFilterOptions::pure_rotation_share,
        "known_rotation: translation undefined when this share of the matches fits the rotation alone");
  field(opt, "cheirality", &DynamicFilterOptions::cheirality,
        "known_rotation: also flag features behind R b1 on their epipolar circle (negative depth if static)");
  field(opt, "epipolar_search", &EpipolarSearchOptions::enabled,
        "re-search dynamic-flagged features along their epipolar line before the flag counts");
  field(opt, "epipolar_search_range_px", &EpipolarSearchOptions::search_half_px,
        "1-D seeds up to this far along the line (0: the nearest point only)");
  field(opt, "epipolar_search_ncc_drop", &EpipolarSearchOptions::max_ncc_drop,
        "re-found iff its patch NCC >= the track's minus this");
  field(opt, "epipolar_search_min_ncc", &EpipolarSearchOptions::min_ncc, "and its patch NCC >= this");
  field(opt, "affine_realign", &AffineRealignOptions::enabled,
        "align dynamic-flagged features' patches over their test's baseline by an affine warp (ECC) before the flag "
        "counts; the track moves there");
  field(opt, "affine_min_correlation", &AffineRealignOptions::min_correlation,
        "affine_realign: the alignment's normalized correlation must reach this");
  field(opt, "affine_refit_model", &AffineRealignOptions::refit_model,
        "affine_realign: fit the camera's motion again when features turn static, and re-align what it flags");
  field(opt, "group_min_support", &DynamicGroupOptions::min_support,
        "a dynamic flag stands only with at least this many other flags near it (0: off)");
  field(opt, "group_radius_factor", &DynamicGroupOptions::radius_factor,
        "the group rule's neighbourhood, in multiples of min_distance_px");
  field(opt, "group_turned_min_support", &DynamicGroupOptions::turned_min_support,
        "a flag on a track static in its last group_turned_static_tests tests needs this many other flags near it");
  field(opt, "group_turned_static_tests", &DynamicGroupOptions::turned_static_tests,
        "static tests in a row that make a newly flagged track 'turned'");
  named_field(opt, "gyro_klt", &FeatureTrackerOptions::gyro_klt, gyro_klt_name, parse_gyro_klt,
              "KLT seeded by the rotation given to process(): 'off', 'seed' ('on') or 'candidate'");
  opt.def_readwrite("baseline_frames", &ImageFrontendOptions::baseline_frames, "longest baseline of the test")
      .def_readwrite("consistency_checks", &ImageFrontendOptions::consistency_checks)
      .def_readwrite("consistency_hits", &ImageFrontendOptions::consistency_hits)
      .def_readwrite("trusted_model", &ImageFrontendOptions::trusted_model,
                     "fit the camera's motion on the tracks static in their last test")
      .def_readwrite("trusted_min_tests", &ImageFrontendOptions::trusted_min_tests,
                     "tests a track needs before it can be trusted")
      .def_readwrite("trust_contest_ratio", &ImageFrontendOptions::trust_contest_ratio,
                     "the trusted model gives way when the model of the tracks it flags passes more than this many "
                     "times as many matches (0: off)")
      .def_readwrite("trust_contest_frames", &ImageFrontendOptions::trust_contest_frames,
                     "the contest runs within this many frames of a cold start (a model fitted on all matches; < 0: "
                     "always)")
      .def_readwrite("young_trust_majority", &ImageFrontendOptions::young_trust_majority,
                     "within trust_contest_frames of a cold start, a frame's flags claim movers only when its static "
                     "features number at least trust_contest_ratio times its flags (else they are isolated)")
      .def_readwrite("mover_grace_claims", &ImageFrontendOptions::mover_grace_claims,
                     "a track claimed as a mover in each of its last this many frames keeps its flag through one test "
                     "under the threshold (0: off)")
      .def("__repr__", [](const py::object& self) { return repr_from_fields(self, "FrontendOptions", kOptionFields); });

  py::class_<FrontendFrame>(m, "FrontendFrame",
                            "One frame of the front end: per feature its id, pixel (N×2), motion (0 unknown, "
                            "1 static, 2 dynamic) and baseline; the frame's counts, M and status.")
      .def_readonly("ids", &FrontendFrame::ids)
      .def_readonly("uv", &FrontendFrame::uv)
      .def_readonly("motion", &FrontendFrame::motion)
      .def_readonly("baseline", &FrontendFrame::baseline)
      .def_readonly("isolated", &FrontendFrame::isolated,
                    "per feature: a dynamic flag (motion 2) without a flagged neighbour; not counted in n_dynamic")
      .def_readonly("graced", &FrontendFrame::graced,
                    "per feature: flagged (motion 2) through a test under the threshold by its run of claims "
                    "(mover_grace_claims)")
      .def_readonly("static_ratio", &FrontendFrame::static_ratio, "M = static / (static + dynamic + isolated)")
      .def_readonly("n_static", &FrontendFrame::n_static)
      .def_readonly("n_dynamic", &FrontendFrame::n_dynamic)
      .def_readonly("n_unknown", &FrontendFrame::n_unknown)
      .def_readonly("tracked", &FrontendFrame::tracked)
      .def_readonly("detected", &FrontendFrame::detected)
      .def_readonly("status", &FrontendFrame::status)
      .def_readonly("motion_model", &FrontendFrame::motion_model,
                    "estimated, known_rotation, pure_rotation or rotation_rejected (the longest test's model)")
      .def_readonly("gyro_seeded", &FrontendFrame::gyro_seeded, "KLT was seeded by the given rotation (gyro_klt)")
      .def_readonly("n_realigned_affine", &FrontendFrame::n_realigned_affine,
                    "dynamic-flagged features moved by the affine re-alignment (affine_realign)")
      .def_readonly("n_unflagged_affine", &FrontendFrame::n_unflagged_affine, "of those, the ones that turned static")
      .def_readonly("n_isolated", &FrontendFrame::n_isolated,
                    "dynamic flags without another flag within the group radius (not counted in n_dynamic)")
      .def_readonly("n_contests_lost", &FrontendFrame::n_contests_lost,
                    "tests whose trusted model gave way to the model of the tracks it flagged (trust_contest_ratio)")
      .def_readonly("trust_undecided", &FrontendFrame::trust_undecided,
                    "young trust without a majority (young_trust_majority): every flag of the frame is isolated")
      .def_readonly("n_graced", &FrontendFrame::n_graced, "flags kept through a test under the threshold (mover_grace_claims)")
      .def_readonly("tracking_ms", &FrontendFrame::tracking_ms)
      .def_readonly("classification_ms", &FrontendFrame::classification_ms)
      .def("__repr__", [](const FrontendFrame& f) {
        return "FrontendFrame(features=" + std::to_string(f.ids.size()) + ", static=" + std::to_string(f.n_static) +
               ", dynamic=" + std::to_string(f.n_dynamic) + ", status='" + f.status + "')";
      });

  py::class_<ImageFrontend>(m, "ImageFrontend",
                            "The DVI front end on a stream of images: ImageFrontend(options=None, calib='', "
                            "mask=None, **option_keywords); process(image) tracks and classifies the next frame.")
      .def(py::init([](const py::object& options, const std::string& calib, const py::object& mask,
                       const py::kwargs& kw) {
             ImageFrontendOptions o = options_from(options, kw);
             GrayImage mask_image = mask.is_none() ? GrayImage{} : to_gray(mask, "mask");
             return ImageFrontend(o, camera_from(calib), std::move(mask_image));
           }),
           py::arg("options") = py::none(), py::arg("calib") = "", py::arg("mask") = py::none())
      .def(
          "process",
          [](ImageFrontend& f, const py::object& image, const py::object& rotation) {
            const GrayImage frame = to_gray(image, "image");
            Eigen::Matrix3d R;
            if (!rotation.is_none()) {
              const RowMatrixXd m = to_rows(rotation, 3, "rotation");
              if (m.rows() != 3) throw py::value_error("rotation: expected a 3x3 matrix");
              R = m;
            }
            FrontendFrameResult r;
            {
              py::gil_scoped_release release;
              r = f.process(frame, rotation.is_none() ? nullptr : &R);
            }
            return to_frame(r);
          },
          py::arg("image"), py::arg("rotation") = py::none(),
          "Tracks and classifies the next frame (2-D uint8). rotation (3x3, optional): the camera's rotation from "
          "the previous frame to this one (x_cur = R x_prev + t), used with known_rotation and gyro_klt. ValueError if the "
          "frame's size differs from the previous frame's or the mask's.")
      .def_property_readonly("options", &ImageFrontend::options);

  m.def(
      "classify_matches",
      [](const py::object& prev, const py::object& cur, const std::string& calib, double threshold_px,
         double ransac_threshold_px, double static_camera_flow_px) {
        require_finite(threshold_px, "threshold_px");
        require_finite(ransac_threshold_px, "ransac_threshold_px");
        const std::vector<Eigen::Vector2d> p1 = to_pixels(prev, "prev"), p2 = to_pixels(cur, "cur");
        if (p1.size() != p2.size()) throw py::value_error("prev and cur: different numbers of matches");
        DynamicFilterOptions o;
        o.threshold_px = threshold_px, o.ransac_threshold_px = ransac_threshold_px;
        o.static_camera_flow_px = static_camera_flow_px;
        const DynamicFeatureFilter filter(o, camera_from(calib));
        const Classification c = filter.classify(p1, p2);
        py::array_t<std::int8_t> flags(static_cast<py::ssize_t>(c.flags.size()));
        std::transform(c.flags.begin(), c.flags.end(), flags.mutable_data(),
                       [](FeatureMotion f) { return static_cast<std::int8_t>(f); });
        py::dict out;
        out["motion"] = flags;
        out["distance_px"] = to_array(c.distance_px);
        out["static_ratio"] = c.static_ratio;
        out["status"] = to_string(c.status);
        out["median_flow_px"] = c.median_flow_px;
        out["F"] = c.F;
        return out;
      },
      py::arg("prev"), py::arg("cur"), py::arg("calib") = "", py::arg("threshold_px") = 1.0,
      py::arg("ransac_threshold_px") = 0.5, py::arg("static_camera_flow_px") = 0.5,
      "The epipolar test of DVI on matched pixels prev[i] -> cur[i] (N×2 each): dict with motion (0 unknown, "
      "1 static, 2 dynamic), distance_px, static_ratio, status, median_flow_px and F. calib: a Kalibr camchain "
      "whose cam0 undistorts the pixels (default: pixels taken as pinhole).");

  m.def(
      "read_gray_image", [](const std::string& path) { return to_numpy(read_gray_image(path)); }, py::arg("path"),
      "An image file (PNG, JPEG, ...) as a 2-D uint8 array (colour converted to gray); InputError if unreadable.");
}

}  // namespace slamkit::python
