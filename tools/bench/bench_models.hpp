/* SPDX-License-Identifier: BSD-3-Clause */
// bench_models.hpp - the pieces the benchmark drivers (fk_bench, ik_bench)
// share, so each exists once: the puma560 and panda models written
// independently of kinctl from the tables in tests/vectors/fk.json, built
// as KDL chains and Pinocchio models; running a kinctl helper and parsing
// its numbers and timed blocks; pinning to one CPU.
//
// The models are factored differently from kinctl's builders (fixed
// placement, then Rz(q)), so agreement with kinctl also tests its models.
#ifndef KINCTL_BENCH_MODELS_HPP
#define KINCTL_BENCH_MODELS_HPP

#include <sched.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include <kdl/chain.hpp>
#include <kdl/frames.hpp>

#ifdef KC_BENCH_WITH_PINOCCHIO
#include <pinocchio/multibody.hpp>
#endif

namespace kcb {

// ---- models, as plain rigid transforms ----

struct Xform {
    double R[3][3];
    double p[3];
};

inline Xform identity()
{
    return Xform{{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}, {0, 0, 0}};
}

inline Xform rot_x(double a)
{
    double c = std::cos(a), s = std::sin(a);
    return Xform{{{1, 0, 0}, {0, c, -s}, {0, s, c}}, {0, 0, 0}};
}

inline Xform rot_z(double a)
{
    double c = std::cos(a), s = std::sin(a);
    return Xform{{{c, -s, 0}, {s, c, 0}, {0, 0, 1}}, {0, 0, 0}};
}

inline Xform trans(double x, double y, double z)
{
    Xform t = identity();
    t.p[0] = x;
    t.p[1] = y;
    t.p[2] = z;
    return t;
}

inline Xform operator*(const Xform &a, const Xform &b)
{
    Xform r{};
    for (int i = 0; i < 3; i++) {
        for (int j = 0; j < 3; j++)
            for (int k = 0; k < 3; k++)
                r.R[i][j] += a.R[i][k] * b.R[k][j];
        r.p[i] = a.p[i];
        for (int k = 0; k < 3; k++)
            r.p[i] += a.R[i][k] * b.p[k];
    }
    return r;
}

// A serial arm of revolute joints about their local z: the tool pose is
// before[0] Rz(q0) before[1] Rz(q1) ... Rz(q_{n-1}) tip.
struct Arm {
    std::vector<Xform> before;
    Xform tip;
};

// Standard DH, A_i = Rz(q_i) Tz(d_i) Tx(a_i) Rx(alpha_i): everything after
// Rz(q_i) is fixed and goes before the next joint (fk.json, rtb Puma560).
inline Arm make_puma560()
{
    const double a[6] = {0.0, 0.4318, 0.0203, 0.0, 0.0, 0.0};
    const double d[6] = {0.67183, 0.0, 0.15005, 0.4318, 0.0, 0.0};
    const double alpha[6] = {M_PI_2, 0.0, -M_PI_2, M_PI_2, -M_PI_2, 0.0};
    Arm arm;
    arm.before.push_back(identity());
    for (int i = 0; i < 6; i++) {
        Xform after = trans(0, 0, d[i]) * trans(a[i], 0, 0) * rot_x(alpha[i]);
        if (i < 5)
            arm.before.push_back(after);
        else
            arm.tip = after;
    }
    return arm;
}

// Modified DH, A_i = Rx(alpha_{i-1}) Tx(a_{i-1}) Rz(q_i) Tz(d_i), then the
// tool Rz(-pi/4) Tz(0.103) (fk.json, rtb Panda).
inline Arm make_panda()
{
    const double a_prev[7] = {0.0, 0.0, 0.0, 0.0825, -0.0825, 0.0, 0.088};
    const double alpha_prev[7] = {0.0, -M_PI_2, M_PI_2, M_PI_2, -M_PI_2, M_PI_2, M_PI_2};
    const double d[7] = {0.333, 0.0, 0.316, 0.0, 0.384, 0.0, 0.107};
    Arm arm;
    for (int i = 0; i < 7; i++) {
        Xform pre = rot_x(alpha_prev[i]) * trans(a_prev[i], 0, 0);
        arm.before.push_back(i == 0 ? pre : trans(0, 0, d[i - 1]) * pre);
    }
    arm.tip = trans(0, 0, d[6]) * rot_z(-M_PI / 4) * trans(0, 0, 0.103);
    return arm;
}


// ---- Orocos KDL ----

inline KDL::Frame to_kdl(const Xform &x)
{
    return KDL::Frame(KDL::Rotation(x.R[0][0], x.R[0][1], x.R[0][2], x.R[1][0], x.R[1][1], x.R[1][2], x.R[2][0],
                                    x.R[2][1], x.R[2][2]),
                      KDL::Vector(x.p[0], x.p[1], x.p[2]));
}

// One segment per joint (Rz(q) then the fixed part up to the next joint), so
// KDL walks no more segments than the arm has joints; a fixed segment only
// for a non-identity base part.
inline KDL::Chain kdl_chain(const Arm &arm)
{
    KDL::Chain chain;
    KDL::Frame base = to_kdl(arm.before[0]);
    if (!KDL::Equal(base, KDL::Frame::Identity(), 0.0))
        chain.addSegment(KDL::Segment(KDL::Joint(KDL::Joint::None), base));
    for (size_t i = 0; i < arm.before.size(); i++) {
        const Xform &next = i + 1 < arm.before.size() ? arm.before[i + 1] : arm.tip;
        chain.addSegment(KDL::Segment(KDL::Joint(KDL::Joint::RotZ), to_kdl(next)));
    }
    return chain;
}

// ---- Pinocchio ----

#ifdef KC_BENCH_WITH_PINOCCHIO
inline pinocchio::SE3 to_pin(const Xform &x)
{
    Eigen::Matrix3d R;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            R(i, j) = x.R[i][j];
    return pinocchio::SE3(R, Eigen::Vector3d(x.p[0], x.p[1], x.p[2]));
}

struct PinArm {
    pinocchio::Model model;
    pinocchio::FrameIndex tool = 0;
};

// Each joint is placed by the fixed part before it; the tool is an
// operational frame on the last joint. No bodies: kinematics needs none.
inline PinArm pin_arm(const Arm &arm)
{
    PinArm p;
    pinocchio::JointIndex parent = 0;
    for (size_t i = 0; i < arm.before.size(); i++)
        parent = p.model.addJoint(parent, pinocchio::JointModelRZ(), to_pin(arm.before[i]), "j" + std::to_string(i + 1));
    p.tool = p.model.addFrame(pinocchio::Frame("tool", parent, to_pin(arm.tip), pinocchio::OP_FRAME));
    return p;
}
#endif

// ---- the kinctl helpers (other processes: see bench_common.h) ----

// Runs a helper with arguments and returns its output; false if it failed.
inline bool run_helper(const char *path, const std::string &args, std::string &out)
{
    std::string cmd = std::string(path) + " " + args;
    FILE *f = popen(cmd.c_str(), "r");
    if (f == nullptr) {
        std::printf("error: cannot run %s\n", cmd.c_str());
        return false;
    }
    out.clear();
    char buf[65536];
    for (size_t n; (n = std::fread(buf, 1, sizeof buf, f)) > 0;)
        out.append(buf, n);
    int rc = pclose(f);
    if (rc != 0) {
        std::printf("error: %s exited with status %d:\n%s\n", cmd.c_str(), rc, out.c_str());
        return false;
    }
    return true;
}

inline std::vector<double> parse_numbers(const char *s)
{
    std::vector<double> v;
    char *end;
    for (double x = std::strtod(s, &end); end != s; x = std::strtod(s, &end)) {
        v.push_back(x);
        s = end;
    }
    return v;
}

// One timed block from a helper (`helper time <what> <n_batches>`, see
// bench_common.h): appends its per-batch times to ns, adds its checksum.
inline bool helper_block(const char *path, const std::string &what, int n_batches, std::vector<double> &ns,
                         double &checksum)
{
    std::string out;
    if (!run_helper(path, "time " + what + " " + std::to_string(n_batches), out))
        return false;
    size_t ns_at = out.find("ns "), sum_at = out.find("checksum ");
    if (ns_at != 0 || sum_at == std::string::npos) {
        std::printf("error: %s: unexpected output:\n%s\n", path, out.c_str());
        return false;
    }
    std::vector<double> v = parse_numbers(out.c_str() + 3);
    if (v.size() != (size_t)n_batches) {
        std::printf("error: %s gave %zu timings, not %d\n", path, v.size(), n_batches);
        return false;
    }
    ns.insert(ns.end(), v.begin(), v.end());
    checksum += std::strtod(out.c_str() + sum_at + 9, nullptr);
    return true;
}

// The last CPU we may run on: on a small machine CPU 0 takes most interrupts.
inline std::string pin_to_one_cpu()
{
    cpu_set_t set;
    if (sched_getaffinity(0, sizeof set, &set) != 0)
        return std::string("not pinned: sched_getaffinity: ") + std::strerror(errno);
    int cpu = -1;
    for (int c = 0; c < CPU_SETSIZE; c++)
        if (CPU_ISSET(c, &set))
            cpu = c;
    CPU_ZERO(&set);
    CPU_SET(cpu, &set);
    if (sched_setaffinity(0, sizeof set, &set) != 0)
        return std::string("not pinned: sched_setaffinity: ") + std::strerror(errno);
    return "pinned to CPU " + std::to_string(cpu);
}

} // namespace kcb

#endif // KINCTL_BENCH_MODELS_HPP
