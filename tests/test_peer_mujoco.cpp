// mbgen's MJCF loader and generic runtime against MuJoCo 2.2 (Debian libmujoco), a peer that
// reads the same XML with its own compiler: body poses, mass matrix and bias forces at seeded
// random states, on unitree_h1 (19 hinges + free), cassie (20 hinges + 2 balls + free) and
// tests/data/mjcf/peer_mix.xml (anchors off the body origin, refs, a slide, two joints in a body,
// a ball at an anchor, every orientation attribute, degrees, a tilted gravity).
//
// Coordinates. MuJoCo's free joint: qpos = [x y z, qw qx qy qz], qvel = [linear velocity of the
// body origin in the WORLD frame, angular velocity in the BODY frame]; mbgen: q = [x y z, qx qy qz
// qw], v = [linear and angular velocity, both in the body frame]. So qvel = T v with T = diag(R_WB,
// I, I...) and, from equal kinetic energy and power,
//     M_mbgen = T^T M_mj T,     b_mbgen = T^T (b_mj + M_mj Tdot v),   Tdot v = [R_WB (w x v_B); 0].
// A ball joint is compared at the identity, where mbgen's x-y-z hinge chain at zero angles has
// rates equal to MuJoCo's ball angular velocity (child frame), and the chain adds Tdot v =
// (wy wz, -wx wz, wx wy) for its rates (wx, wy, wz).
//
// Both sides carry the joint armature on the diagonal of M. qfrc_bias (Coriolis, centrifugal and
// gravity) holds neither damping, springs (qfrc_passive) nor equality constraints (solver), so
// nothing is disabled. The files' meshes are not in the store: the test hands MuJoCo a copy
// without <asset>, mesh geoms and materials, which changes no inertia (every body has an
// <inertial>).
#include <gtest/gtest.h>
#include <mujoco/mujoco.h>
#include <tinyxml2.h>

#include <Eigen/Geometry>
#include <cstdio>
#include <fstream>
#include <filesystem>
#include <random>

#include "load/fit_link_ssvs.hpp"
#include "mesh_shapes.hpp"
#include "mesh/mesh_path.hpp"
#include "mesh/read_mesh.hpp"
#include "mujoco_without_assets.hpp"
#include "test_support.hpp"

namespace mbgen::test {
namespace {

/// The file without what MuJoCo would have to load from disk (meshes, textures) or look up.
std::string strip_assets(const std::string& path, const std::string& name) {
  tinyxml2::XMLDocument doc;
  EXPECT_EQ(doc.LoadFile(path.c_str()), tinyxml2::XML_SUCCESS);
  remove_mujoco_assets(doc);
  const std::string out = (std::filesystem::temp_directory_path() / ("mbgen_peer_mujoco_" + name + ".xml")).string();
  EXPECT_EQ(doc.SaveFile(out.c_str()), tinyxml2::XML_SUCCESS);
  return out;
}

struct MujocoCase {
  std::string name, path;
  double tol_inertia, tol_dynamics;  ///< relative, see the cases below
};
void PrintTo(const MujocoCase& c, std::ostream* os) { *os << c.name; }

class PeerMujoco : public ::testing::TestWithParam<MujocoCase> {
 protected:
  void SetUp() override {
    const std::string& path = GetParam().path;
    gen::LoadOptions options;
    options.pick_up_robot_yaml = false;
    model_ = gen::load_description(path, options).model;
    char error[1000] = "";
    m_ = mj_loadXML(strip_assets(path, GetParam().name).c_str(), nullptr, error, sizeof error);
    ASSERT_TRUE(m_) << error;
    d_ = mj_makeData(m_);
    ASSERT_EQ(m_->nv, model_.nv());
    // Map every mbgen joint to MuJoCo's qpos / dof addresses.
    for (int j = 1; j < model_.num_joints(); ++j) {
      const Joint& joint = model_.joint(JointIndex(j));
      Map map{&joint, -1, -1, -1};  // ball_axis: -1 unless a ball's hinge
      int id = mj_name2id(m_, mjOBJ_JOINT, joint.name.c_str());
      if (joint.type == JointType::Floating) {
        for (int k = 0; k < m_->njnt; ++k)
          if (m_->jnt_type[k] == mjJNT_FREE) id = k;
      } else if (id < 0) {  // a ball's hinge "<ball>_x|y|z"
        const std::string ball = joint.name.substr(0, joint.name.size() - 2);
        id = mj_name2id(m_, mjOBJ_JOINT, ball.c_str());
        ASSERT_GE(id, 0) << joint.name;
        ASSERT_EQ(m_->jnt_type[id], mjJNT_BALL);
        map.ball_axis = joint.name.back() - 'x';
      }
      ASSERT_GE(id, 0) << joint.name;
      map.qpos = m_->jnt_qposadr[id];
      map.dof = m_->jnt_dofadr[id] + std::max(map.ball_axis, 0);
      maps_.push_back(map);
    }
  }
  void TearDown() override {
    if (d_) mj_deleteData(d_);
    if (m_) mj_deleteModel(m_);
  }

  struct Map {
    const Joint* joint;
    int qpos, dof, ball_axis;
  };

  /// Random hinge angles, balls at the identity (their hinges at 0), a random base pose.
  VecX<double> random_q(std::mt19937_64& rng) const {
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    VecX<double> q = VecX<double>::Zero(model_.nq());
    for (const Map& m : maps_) {
      if (m.joint->type == JointType::Floating) {
        const Eigen::Quaterniond r = Eigen::Quaterniond(u(rng), u(rng), u(rng), u(rng)).normalized();
        q.segment<7>(m.joint->idx_q) << u(rng), u(rng), 1 + u(rng), r.x(), r.y(), r.z(), r.w();
      } else if (m.ball_axis < 0) {
        q[m.joint->idx_q] = 3 * u(rng);
      }
    }
    return q;
  }

  /// Sets MuJoCo's qpos and qvel from mbgen's (q, v) and returns T (qvel = T v) and Tdot v.
  void to_mujoco(const VecX<double>& q, const VecX<double>& v, MatX<double>& T, VecX<double>& Tdot_v) const {
    const int n = model_.nv();
    T = MatX<double>::Zero(n, n);
    Tdot_v = VecX<double>::Zero(n);
    for (int k = 0; k < m_->nq; ++k) d_->qpos[k] = 0;
    for (const Map& m : maps_) {
      const int iq = m.joint->idx_q, iv = m.joint->idx_v;
      if (m.joint->type == JointType::Floating) {
        for (int k = 0; k < 3; ++k) d_->qpos[m.qpos + k] = q[iq + k];
        d_->qpos[m.qpos + 3] = q[iq + 6];
        for (int k = 0; k < 3; ++k) d_->qpos[m.qpos + 4 + k] = q[iq + 3 + k];
        const Mat3<double> R = Eigen::Quaterniond(q[iq + 6], q[iq + 3], q[iq + 4], q[iq + 5]).toRotationMatrix();
        T.block<3, 3>(m.dof, iv) = R;
        T.block<3, 3>(m.dof + 3, iv + 3).setIdentity();
        const Vec3<double> vB = v.segment<3>(iv), w = v.segment<3>(iv + 3);
        Tdot_v.segment<3>(m.dof) = R * w.cross(vB);
      } else if (m.ball_axis >= 0) {
        if (m.ball_axis == 0) {
          d_->qpos[m.qpos] = 1;  // identity quaternion, w first
          const double wx = v[iv], wy = v[iv + 1], wz = v[iv + 2];
          Tdot_v.segment<3>(m.dof) << wy * wz, -wx * wz, wx * wy;
        }
        T(m.dof, iv) = 1;
      } else {
        d_->qpos[m.qpos] = q[iq];
        T(m.dof, iv) = 1;
      }
    }
    const VecX<double> qvel = T * v;
    for (int k = 0; k < n; ++k) d_->qvel[k] = qvel[k];
  }

  MatX<double> mujoco_mass_matrix() const {
    MatX<double> M(m_->nv, m_->nv);
    std::vector<mjtNum> dense(m_->nv * m_->nv);
    mj_fullM(m_, dense.data(), d_->qM);
    for (int r = 0; r < m_->nv; ++r)
      for (int c = 0; c < m_->nv; ++c) M(r, c) = dense[r * m_->nv + c];
    return M;
  }

  /// Body b's inertia as MuJoCo compiled it (principal moments body_inertia in the frame
  /// body_iquat at body_ipos), in the MJCF body frame.
  Inertia<double> mujoco_inertia(int b) const {
    const Mat3<double> R = Eigen::Quaterniond(m_->body_iquat[4 * b], m_->body_iquat[4 * b + 1], m_->body_iquat[4 * b + 2],
                                              m_->body_iquat[4 * b + 3]).toRotationMatrix();
    const Vec3<double> d(m_->body_inertia[3 * b], m_->body_inertia[3 * b + 1], m_->body_inertia[3 * b + 2]);
    Inertia<double> I;
    I.mass = m_->body_mass[b];
    I.com = Vec3<double>(m_->body_ipos[3 * b], m_->body_ipos[3 * b + 1], m_->body_ipos[3 * b + 2]);
    I.inertia_com = R * d.asDiagonal() * R.transpose();
    return I;
  }

  /// Worst relative errors of crba and rnea(q, v, 0) on `model` against MuJoCo over seeded states.
  void run_dynamics(const Model& model, double& worst_M, double& worst_b) {
    Data<double> data(model);
    std::mt19937_64 rng(5);
    for (int trial = 0; trial < kStates; ++trial) {
      const VecX<double> q = random_q(rng);
      const VecX<double> v = random_vector<double>(model.nv(), rng, 2.0);
      MatX<double> T;
      VecX<double> Tdot_v;
      to_mujoco(q, v, T, Tdot_v);
      mj_forward(m_, d_);
      const MatX<double> M_mj = mujoco_mass_matrix();
      VecX<double> b_mj(model.nv());
      for (int k = 0; k < model.nv(); ++k) b_mj[k] = d_->qfrc_bias[k];
      const MatX<double> M = crba<double>(model, data, q);
      const VecX<double> b = rnea<double>(model, data, q, v, VecX<double>::Zero(model.nv()));
      worst_M = std::max(worst_M, relative_error(M, MatX<double>(T.transpose() * M_mj * T)));
      worst_b = std::max(worst_b, relative_error(b, VecX<double>(T.transpose() * (b_mj + M_mj * Tdot_v))));
    }
  }

  static constexpr int kStates = 50;
  Model model_;
  mjModel* m_ = nullptr;
  mjData* d_ = nullptr;
  std::vector<Map> maps_;
};

TEST_P(PeerMujoco, BodyPosesAgree) {
  Data<double> data(model_);
  std::mt19937_64 rng(3);
  double worst = 0;
  for (int trial = 0; trial < kStates; ++trial) {
    const VecX<double> q = random_q(rng);
    MatX<double> T;
    VecX<double> Tdot_v;
    to_mujoco(q, VecX<double>::Zero(model_.nv()), T, Tdot_v);
    mj_forward(m_, d_);
    forward_kinematics<double>(model_, data, q);
    update_frame_placements<double>(model_, data);
    for (int b = 1; b < m_->nbody; ++b) {
      const char* name = mj_id2name(m_, mjOBJ_BODY, b);
      ASSERT_TRUE(name);
      const SE3<double>& X = data.X_WF[model_.frame_index(name)];
      Mat3<double> R;
      for (int k = 0; k < 9; ++k) R(k / 3, k % 3) = d_->xmat[9 * b + k];
      const Vec3<double> p(d_->xpos[3 * b], d_->xpos[3 * b + 1], d_->xpos[3 * b + 2]);
      worst = std::max({worst, (X.translation - p).norm(), (X.rotation - R).norm()});
    }
  }
  std::printf("  %s body poses: worst difference %.2e\n", GetParam().name.c_str(), worst);
  EXPECT_LT(worst, 1e-12);
}

/// MuJoCo's compiler also places a connect's body2 point at qpos0 (eq_data[3..6]): the same
/// rule the loader follows, computed by another implementation (cassie's four rods).
TEST_P(PeerMujoco, ConnectAnchorsAgree) {
  gen::LoadOptions options;
  options.pick_up_robot_yaml = false;
  const gen::Description d = gen::load_description(GetParam().path, options);
  ASSERT_EQ(static_cast<int>(d.closures.size()), m_->neq);
  double worst = 0;
  for (int i = 0; i < m_->neq; ++i) {
    const gen::ClosureSpec& c = d.closures[i];
    ASSERT_EQ(m_->eq_type[i], mjEQ_CONNECT);
    EXPECT_EQ(c.frame_a, mj_id2name(m_, mjOBJ_BODY, m_->eq_obj1id[i]));
    EXPECT_EQ(c.frame_b, mj_id2name(m_, mjOBJ_BODY, m_->eq_obj2id[i]));
    const mjtNum* data = m_->eq_data + i * mjNEQDATA;
    worst = std::max({worst, (c.X_AC.translation - Vec3<double>(data[0], data[1], data[2])).norm(),
                      (c.X_BC.translation - Vec3<double>(data[3], data[4], data[5])).norm()});
  }
  std::printf("  %s connect anchors: %d, worst difference %.2e m\n", GetParam().name.c_str(), m_->neq, worst);
  EXPECT_LT(worst, 1e-12);
}

/// What mj_loadXML did to the inertias: MuJoCo keeps each body's inertia as principal moments in
/// a principal frame; a fullinertia is diagonalised by its compiler (DESIGN.md). Compared with the
/// inertia mbgen read, per body not merged into another (same mass on both sides).
TEST_P(PeerMujoco, InertiasAsCompiled) {
  double worst = 0;
  for (int b = 1; b < m_->nbody; ++b) {
    const std::string name = mj_id2name(m_, mjOBJ_BODY, b);
    const auto body = model_.find_body(name);
    if (!body || std::abs(model_.body(*body).inertia.mass - m_->body_mass[b]) > 1e-15) continue;
    const Frame& frame = model_.frame(model_.frame_index(name));
    // mbgen's inertia about the CoM, in the MJCF body frame.
    const Mat3<double> R_FB = frame.X_BF.rotation;
    const Mat3<double> I_mb = R_FB.transpose() * model_.body(*body).inertia.inertia_com * R_FB;
    worst = std::max(worst, (I_mb - mujoco_inertia(b).inertia_com).norm() / I_mb.norm());
  }
  std::printf("  %s inertias: worst relative difference after MuJoCo's compiler %.2e\n", GetParam().name.c_str(), worst);
  EXPECT_LT(worst, GetParam().tol_inertia);
}

TEST_P(PeerMujoco, MassMatrixAndBias) {
  double worst_M = 0, worst_b = 0;
  run_dynamics(model_, worst_M, worst_b);
  std::printf("  %s vs MuJoCo: mass matrix %.2e, bias %.2e (worst relative)\n", GetParam().name.c_str(), worst_M, worst_b);
  EXPECT_LT(worst_M, GetParam().tol_dynamics);
  EXPECT_LT(worst_b, GetParam().tol_dynamics);
}

TEST_P(PeerMujoco, MassMatrixAndBiasWithMujocosInertias) {
  Model model = model_;
  for (int b = 1; b < model.num_bodies(); ++b) model.mutable_body(BodyIndex(b)).inertia = Inertia<double>{};
  for (int b = 1; b < m_->nbody; ++b) {
    const Frame& frame = model.frame(model.frame_index(mj_id2name(m_, mjOBJ_BODY, b)));
    Body& body = model.mutable_body(frame.body);
    body.inertia = body.inertia + mujoco_inertia(b).transformed(frame.X_BF);
  }
  double worst_M = 0, worst_b = 0;
  run_dynamics(model, worst_M, worst_b);
  std::printf("  %s vs MuJoCo with MuJoCo's inertias: mass matrix %.2e, bias %.2e\n", GetParam().name.c_str(), worst_M,
              worst_b);
  EXPECT_LT(worst_M, 1e-12);
  EXPECT_LT(worst_b, 1e-12);
}

// Mesh geoms (load/mjcf_geoms.cpp): MuJoCo moves each mesh to its inertial frame and offsets the
// geom to match; mbgen places the file's vertices by the mesh's scale and the geom's pose. Both
// must put every vertex at the same point of the body. An off-centre, tilted tetrahedron (so the
// inertial frame is neither the file's origin nor its axes), scaled unevenly, under a meshdir,
// once with pos + euler in degrees and once with a class default's quat.
TEST(PeerMujocoMeshes, MeshVerticesLandWhereMujocoPutsThem) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / "mbgen_peer_mujoco_mesh";
  fs::create_directories(dir / "assets");
  mesh::TriangleMesh tetrahedron;
  tetrahedron.vertices = {{0.3, 0.1, 0.2}, {0.5, 0.1, 0.25}, {0.3, 0.4, 0.2}, {0.35, 0.15, 0.6}};
  tetrahedron.triangles = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  write_binary_stl((dir / "assets" / "tet.stl").string(), tetrahedron);
  std::ofstream(dir / "meshes.xml") << R"(<mujoco model="meshes">
  <compiler angle="degree" meshdir="assets"/>
  <default><default class="turned"><geom type="mesh" quat="0.9 0.1 -0.3 0.2"/></default></default>
  <asset><mesh name="tet" file="tet.stl" scale="1.5 0.8 1.2"/><mesh name="plain" file="tet.stl"/></asset>
  <worldbody>
    <body name="a" pos="0 0 1">
      <joint name="j" type="hinge" axis="0 1 0"/>
      <inertial pos="0 0 0" mass="1" diaginertia="0.01 0.01 0.01"/>
      <geom name="g1" type="mesh" mesh="tet" pos="0.1 -0.2 0.05" euler="10 -20 30"/>
      <body name="b" pos="0.2 0 0">
        <joint name="k" type="hinge" axis="1 0 0"/>
        <inertial pos="0 0 0" mass="1" diaginertia="0.01 0.01 0.01"/>
        <geom name="g2" class="turned" mesh="plain" pos="0 0.1 0"/>
      </body>
    </body>
  </worldbody>
</mujoco>
)";
  char error[1000] = "";
  mjModel* m = mj_loadXML((dir / "meshes.xml").string().c_str(), nullptr, error, sizeof error);
  ASSERT_NE(m, nullptr) << error;
  gen::LoadOptions options;
  options.pick_up_robot_yaml = false;
  gen::Description d = gen::read_description((dir / "meshes.xml").string(), options);
  for (const char* geom_name : {"g1", "g2"}) {
    const int g = mj_name2id(m, mjOBJ_GEOM, geom_name);
    ASSERT_GE(g, 0);
    const std::string body = mj_id2name(m, mjOBJ_BODY, m->geom_bodyid[g]);
    const Eigen::Quaterniond q(m->geom_quat[4 * g], m->geom_quat[4 * g + 1], m->geom_quat[4 * g + 2], m->geom_quat[4 * g + 3]);
    const Vec3<double> p(m->geom_pos[3 * g], m->geom_pos[3 * g + 1], m->geom_pos[3 * g + 2]);
    const int mesh = m->geom_dataid[g];
    std::vector<Vec3<double>> theirs;
    for (int v = 0; v < m->mesh_vertnum[mesh]; ++v) {
      const float* x = m->mesh_vert + 3 * (m->mesh_vertadr[mesh] + v);
      theirs.push_back(p + q.toRotationMatrix() * Vec3<double>(x[0], x[1], x[2]));
    }
    ASSERT_EQ(d.link_meshes.at(body).size(), 1u) << body;
    const gen::MeshGeometry& geometry = d.link_meshes.at(body)[0];
    mesh::TriangleMesh ours;
    mesh::append_transformed(mesh::read_mesh(mesh::resolve_mesh_path(geometry.reference, dir.string(), {})), geometry.scale,
                             geometry.X_LG, ours);
    // Every MuJoCo vertex is one of ours and every one of ours one of MuJoCo's (float storage).
    double worst = 0;
    for (const auto& a : theirs) {
      double nearest = 1e300;
      for (const auto& b : ours.vertices) nearest = std::min(nearest, (a - b).norm());
      worst = std::max(worst, nearest);
    }
    for (const auto& b : ours.vertices) {
      double nearest = 1e300;
      for (const auto& a : theirs) nearest = std::min(nearest, (a - b).norm());
      worst = std::max(worst, nearest);
    }
    std::printf("  %s: %zu MuJoCo vertices, largest distance to mbgen's %.1e m\n", geom_name, theirs.size(), worst);
    EXPECT_LT(worst, 1e-6) << geom_name;
    // The case is not trivial: MuJoCo did move the mesh (its geom sits away from the pos given).
    const Vec3<double> given = std::string(geom_name) == "g1" ? Vec3<double>(0.1, -0.2, 0.05) : Vec3<double>(0, 0.1, 0);
    EXPECT_GT((p - given).norm(), 0.1) << geom_name;
  }
  // The fit encloses MuJoCo's vertices of both bodies.
  const std::vector<gen::LinkFit> fits = gen::fit_link_ssvs(d, {}, mesh::FitOptions{});
  ASSERT_EQ(fits.size(), 2u);
  for (const gen::LinkFit& fit : fits) {
    const int b = mj_name2id(m, mjOBJ_BODY, fit.link.c_str());
    for (int g = 0; g < m->ngeom; ++g) {
      if (m->geom_bodyid[g] != b) continue;
      const Eigen::Quaterniond q(m->geom_quat[4 * g], m->geom_quat[4 * g + 1], m->geom_quat[4 * g + 2], m->geom_quat[4 * g + 3]);
      const Vec3<double> p(m->geom_pos[3 * g], m->geom_pos[3 * g + 1], m->geom_pos[3 * g + 2]);
      const int mesh = m->geom_dataid[g];
      for (int v = 0; v < m->mesh_vertnum[mesh]; ++v) {
        const float* x = m->mesh_vert + 3 * (m->mesh_vertadr[mesh] + v);
        // float storage: MuJoCo's vertex may sit 1e-7 m from the file's.
        EXPECT_LE(mesh::distance_to_compound(p + q.toRotationMatrix() * Vec3<double>(x[0], x[1], x[2]), fit.compound.primitives), 1e-6);
      }
    }
  }
  mj_deleteModel(m);
}

// Tolerances (relative, ||a - b|| / max(1, ||b||)), from what each file's inertias allow:
//  - h1 writes every inertia as diaginertia + quat, which MuJoCo keeps as written: both sides run
//    O(n) recursions in double, so 1e-12 leaves three orders over the round-off seen (~1e-15);
//  - cassie writes fullinertia, which MuJoCo 2.2 diagonalises with an iterative eigen solver that
//    stops early: InertiasAsCompiled sees up to ~2e-7 relative on single (small) body inertias,
//    and M and the bias then differ by ~3e-10 relative. 1e-8 says so, and
//    MassMatrixAndBiasWithMujocosInertias shows that with MuJoCo's own inertias the two agree to
//    round-off (1e-12) on cassie too. A modelling mistake (anchor, ref, ball axes) shows as >= 1e-3;
//  - peer_mix: diagonal inertias as h1, 1e-12.
INSTANTIATE_TEST_SUITE_P(Robots, PeerMujoco,
                         ::testing::Values(MujocoCase{"h1", shared_robot("unitree_h1/h1.xml"), 1e-12, 1e-12},
                                           MujocoCase{"cassie", shared_robot("cassie_mjcf/cassie.xml"), 1e-6, 1e-8},
                                           MujocoCase{"peer_mix", MBGEN_TEST_DATA "/mjcf/peer_mix.xml", 1e-12, 1e-12}),
                         [](const auto& info) { return info.param.name; });

// Couplings (load/mjcf_equality.cpp, load/mjcf_tendons.cpp): mbgen eliminates each follower,
// MuJoCo keeps every joint and holds the equality by its (soft) constraint solver. So MuJoCo's
// side is its unconstrained mass matrix and bias projected onto the leaders by the coupling map
// written here from the file's numbers (q_follower' = ratio q_leader'): T^T M_mj T y'' =
// T^T (tau - b_mj), against mbgen's O(n) forward dynamics of the closed system at the same
// closed state; and MuJoCo's own equality residual (efc_pos) at mbgen's closed poses, which
// checks the offsets (refs, c0, coefs) independently.
struct Coupling {
  const char *follower, *leader;
  double ratio;
};

void expect_closed_dynamics_as_mujocos(const std::string& file, const std::vector<Coupling>& couplings) {
  const std::string path = MBGEN_TEST_DATA "/mjcf/" + file;
  gen::LoadOptions options;
  options.pick_up_robot_yaml = false;
  const gen::Description d = gen::load_description(path, options);
  const Model& model = d.model;
  char error[1000] = "";
  mjModel* m = mj_loadXML(path.c_str(), nullptr, error, sizeof error);
  ASSERT_TRUE(m) << error;
  mjData* md = mj_makeData(m);
  ASSERT_EQ(m->nv, model.nv());
  const int n = model.nv();
  std::vector<int> dof(n);  // mbgen's v index -> MuJoCo's dof
  for (int j = 1; j < model.num_joints(); ++j) {
    const Joint& joint = model.joint(JointIndex(j));
    dof[joint.idx_v] = m->jnt_dofadr[mj_name2id(m, mjOBJ_JOINT, joint.name.c_str())];
  }
  const std::vector<int>& independent = model.structure().independent_v;
  const int ny = static_cast<int>(independent.size());
  ASSERT_EQ(ny, n - static_cast<int>(couplings.size()));
  const auto v_of = [&](const char* name) { return model.joint(*model.find_joint(name)).idx_v; };
  MatX<double> T = MatX<double>::Zero(n, ny);
  for (int k = 0; k < ny; ++k) T(independent[k], k) = 1;
  for (const Coupling& c : couplings) T(v_of(c.follower), model.structure().column_of_v[v_of(c.leader)]) = c.ratio;
  Data<double> data(model);
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  double worst = 0, worst_closure = 0;
  int rows = 0;
  for (int trial = 0; trial < 30; ++trial) {
    VecX<double> q = d.assembly.q;
    for (int y : independent)
      q[model.q_index_of_v(y)] += 0.5 * u(rng) * (model.joint(model.joint_of_v(y)).type == JointType::Prismatic ? 0.02 : 1.0);
    ASSERT_EQ(closure_positions<double>(model, data, q).status, ClosureStatus::Converged);
    VecX<double> vy(ny), v(n);
    for (int k = 0; k < ny; ++k) vy[k] = u(rng);
    full_velocities<double>(model, data, q, vy, v);
    const VecX<double> tau = random_vector<double>(n, rng, 2.0);
    for (int j = 1; j < model.num_joints(); ++j) {
      const Joint& joint = model.joint(JointIndex(j));
      const int id = mj_name2id(m, mjOBJ_JOINT, joint.name.c_str());
      md->qpos[m->jnt_qposadr[id]] = q[joint.idx_q];
      md->qvel[m->jnt_dofadr[id]] = v[joint.idx_v];
    }
    mj_forward(m, md);
    rows = 0;
    for (int r = 0; r < md->nefc; ++r)
      if (md->efc_type[r] == mjCNSTR_EQUALITY) worst_closure = std::max(worst_closure, std::abs(md->efc_pos[r])), ++rows;
    std::vector<mjtNum> dense(n * n);
    mj_fullM(m, dense.data(), md->qM);
    MatX<double> M(n, n);
    VecX<double> b(n);
    for (int r = 0; r < n; ++r) {
      b[r] = md->qfrc_bias[dof[r]];
      for (int c = 0; c < n; ++c) M(r, c) = dense[dof[r] * n + dof[c]];
    }
    const VecX<double> expected = (T.transpose() * M * T).ldlt().solve(T.transpose() * (tau - b));
    ASSERT_EQ(forward_dynamics_loops<double>(model, data, q, v, tau), ClosureStatus::Converged);
    VecX<double> ydd(ny);
    for (int k = 0; k < ny; ++k) ydd[k] = data.ddq[independent[k]];
    worst = std::max(worst, relative_error(ydd, expected));
  }
  std::printf("  %s vs MuJoCo projected: worst relative %.2e; MuJoCo's equality residual %.2e\n", file.c_str(), worst,
              worst_closure);
  EXPECT_EQ(rows, static_cast<int>(couplings.size()));
  EXPECT_LT(worst, 1e-12);
  EXPECT_LT(worst_closure, 1e-15);  // the two programs agree on where each coupling holds
  mj_deleteData(md);
  mj_deleteModel(m);
}

TEST(PeerMujocoCouplings, JointEqualitiesSideBySideAndAlongAChain) {
  // polycoef "0.002 1 0 0 0" and "0.05 0.7 0 0 0"
  expect_closed_dynamics_as_mujocos("joint_coupling.xml", {{"right_slide", "left_slide", 1.0}, {"thumb_tip", "thumb_base", 0.7}});
}

TEST(PeerMujocoCouplings, FixedTendonHeldAtItsLength) {
  // coefs 0.5 and -0.25: q2' = -(0.5 / -0.25) q1' = 2 q1'
  expect_closed_dynamics_as_mujocos("tendon_coupling.xml", {{"finger_joint2", "finger_joint1", 2.0}});
}

}  // namespace
}  // namespace mbgen::test
