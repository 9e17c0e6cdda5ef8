// fk_bench.cpp - FK and Jacobian time per call: kinctl against Orocos KDL and
// Pinocchio on the same DH tables and the same configurations (issue 2).
//
// kinctl's double and float builds share symbol names, so each is timed by
// its own helper executable (kinctl_helper.c) that this driver runs; KDL and
// Pinocchio are timed here, in the same invocation and pinned to the same CPU
// (children inherit the affinity). Before the table is printed every library
// is checked against the others on the first BENCH_CHECKS configurations: a
// benchmark of a wrong computation is worthless, so a mismatch stops it.
//
// The KDL and Pinocchio models are built from the tables in
// tests/vectors/fk.json, written here independently of kinctl's own model
// builders and factored differently (fixed placement, then Rz(q)), so the
// check also tests kinctl's built-in models.

#include <sched.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>
#include <string>
#include <vector>

#include <kdl/chain.hpp>
#include <kdl/chainfksolverpos_recursive.hpp>
#include <kdl/chainjnttojacsolver.hpp>
#include <kdl/frames.hpp>
#include <kdl/jacobian.hpp>
#include <kdl/jntarray.hpp>

#ifdef KC_BENCH_WITH_PINOCCHIO
#include <pinocchio/algorithm/frames.hpp>
#include <pinocchio/algorithm/jacobian.hpp>
#include <pinocchio/algorithm/kinematics.hpp>
#include <pinocchio/multibody.hpp>
#endif

#include "bench_common.h"

namespace {

// ---- models, as plain rigid transforms ----

struct Xform {
    double R[3][3];
    double p[3];
};

Xform identity()
{
    return Xform{{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}, {0, 0, 0}};
}

Xform rot_x(double a)
{
    double c = std::cos(a), s = std::sin(a);
    return Xform{{{1, 0, 0}, {0, c, -s}, {0, s, c}}, {0, 0, 0}};
}

Xform rot_z(double a)
{
    double c = std::cos(a), s = std::sin(a);
    return Xform{{{c, -s, 0}, {s, c, 0}, {0, 0, 1}}, {0, 0, 0}};
}

Xform trans(double x, double y, double z)
{
    Xform t = identity();
    t.p[0] = x;
    t.p[1] = y;
    t.p[2] = z;
    return t;
}

Xform operator*(const Xform &a, const Xform &b)
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
Arm make_puma560()
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
Arm make_panda()
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

// Pose as R row-major then t, and Jacobian as 6 x n row-major (vx vy vz wx
// wy wz): the helpers' order.
struct Result {
    std::vector<double> pose, jac;
};

// ---- Orocos KDL ----

KDL::Frame to_kdl(const Xform &x)
{
    return KDL::Frame(KDL::Rotation(x.R[0][0], x.R[0][1], x.R[0][2], x.R[1][0], x.R[1][1], x.R[1][2], x.R[2][0],
                                    x.R[2][1], x.R[2][2]),
                      KDL::Vector(x.p[0], x.p[1], x.p[2]));
}

// One segment per joint (Rz(q) then the fixed part up to the next joint), so
// KDL walks no more segments than the arm has joints; a fixed segment only
// for a non-identity base part.
KDL::Chain kdl_chain(const Arm &arm)
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

Result kdl_eval(const KDL::Chain &chain, const double *q)
{
    unsigned n = chain.getNrOfJoints();
    KDL::JntArray qa(n);
    for (unsigned j = 0; j < n; j++)
        qa(j) = q[j];
    KDL::ChainFkSolverPos_recursive fk(chain);
    KDL::ChainJntToJacSolver js(chain);
    KDL::Frame f;
    KDL::Jacobian jac(n);
    fk.JntToCart(qa, f);
    js.JntToJac(qa, jac);
    Result r;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            r.pose.push_back(f.M(i, j));
    for (int i = 0; i < 3; i++)
        r.pose.push_back(f.p(i));
    for (unsigned i = 0; i < 6; i++)
        for (unsigned j = 0; j < n; j++)
            r.jac.push_back(jac(i, j));
    return r;
}

// ---- Pinocchio ----

#ifdef KC_BENCH_WITH_PINOCCHIO
pinocchio::SE3 to_pin(const Xform &x)
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
PinArm pin_arm(const Arm &arm)
{
    PinArm p;
    pinocchio::JointIndex parent = 0;
    for (size_t i = 0; i < arm.before.size(); i++)
        parent = p.model.addJoint(parent, pinocchio::JointModelRZ(), to_pin(arm.before[i]), "j" + std::to_string(i + 1));
    p.tool = p.model.addFrame(pinocchio::Frame("tool", parent, to_pin(arm.tip), pinocchio::OP_FRAME));
    return p;
}

Result pin_eval(const PinArm &p, const double *q)
{
    pinocchio::Data data(p.model);
    Eigen::VectorXd qv(p.model.nq);
    for (int j = 0; j < p.model.nq; j++)
        qv[j] = q[j];
    pinocchio::forwardKinematics(p.model, data, qv);
    pinocchio::updateFramePlacement(p.model, data, p.tool);
    pinocchio::Data::Matrix6x J = pinocchio::Data::Matrix6x::Zero(6, p.model.nv);
    pinocchio::computeFrameJacobian(p.model, data, qv, p.tool, pinocchio::LOCAL_WORLD_ALIGNED, J);
    const pinocchio::SE3 &T = data.oMf[p.tool];
    Result r;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            r.pose.push_back(T.rotation()(i, j));
    for (int i = 0; i < 3; i++)
        r.pose.push_back(T.translation()[i]);
    for (int i = 0; i < 6; i++)
        for (int j = 0; j < p.model.nv; j++)
            r.jac.push_back(J(i, j));
    return r;
}
#endif

// ---- the kinctl helpers ----

struct Row {
    std::string lib, model, prec, op;
    bench_stats s;
};

struct HelperOutput {
    std::map<std::string, std::vector<Result>> checks; // by model, by config
    std::vector<Row> rows;
    double checksum = 0.0;
};

std::vector<double> parse_numbers(const char *s)
{
    std::vector<double> v;
    char *end;
    for (double x = std::strtod(s, &end); end != s; x = std::strtod(s, &end)) {
        v.push_back(x);
        s = end;
    }
    return v;
}

bool run_helper(const char *path, const char *prec, HelperOutput &out)
{
    FILE *f = popen(path, "r");
    if (f == nullptr) {
        std::printf("error: cannot run %s\n", path);
        return false;
    }
    char line[16384];
    bool ok = true;
    while (std::fgets(line, sizeof line, f) != nullptr) {
        char model[32], what[8];
        int idx, used = 0;
        if (std::sscanf(line, "check %31s %d %7s %n", model, &idx, what, &used) == 3 && used > 0) {
            std::vector<Result> &v = out.checks[model];
            if ((int)v.size() <= idx)
                v.resize((size_t)idx + 1);
            (std::strcmp(what, "pose") == 0 ? v[(size_t)idx].pose : v[(size_t)idx].jac) = parse_numbers(line + used);
        } else if (std::sscanf(line, "time %31s %7s %n", model, what, &used) == 2 && used > 0) {
            std::vector<double> n = parse_numbers(line + used);
            if (n.size() != 4) {
                ok = false;
                break;
            }
            out.rows.push_back(Row{"kinctl", model, prec, what, bench_stats{n[0], n[1], n[2]}});
            out.checksum += n[3];
        } else {
            std::printf("%s helper: %s", prec, line);
            ok = false;
        }
    }
    int rc = pclose(f);
    if (rc != 0 || !ok) {
        std::printf("error: %s exited with status %d\n", path, rc);
        return false;
    }
    return true;
}

// ---- checks ----

double max_diff(const std::vector<double> &a, const std::vector<double> &b)
{
    if (a.size() != b.size() || a.empty())
        return INFINITY;
    double m = 0.0;
    for (size_t i = 0; i < a.size(); i++)
        m = std::fmax(m, std::fabs(a[i] - b[i]));
    return m;
}

// Prints the largest pose and Jacobian difference over the check set;
// false when either exceeds tol.
bool compare(const char *what, const std::vector<Result> &a, const std::vector<Result> &b, double tol)
{
    double dp = a.size() == b.size() ? 0.0 : INFINITY, dj = dp;
    for (size_t k = 0; k < a.size() && k < b.size(); k++) {
        dp = std::fmax(dp, max_diff(a[k].pose, b[k].pose));
        dj = std::fmax(dj, max_diff(a[k].jac, b[k].jac));
    }
    bool ok = dp <= tol && dj <= tol;
    std::printf("  %-30s pose %8.1e  jacobian %8.1e  %s (tol %.0e)\n", what, dp, dj, ok ? "ok" : "MISMATCH", tol);
    return ok;
}

// The last CPU we may run on: on a small machine CPU 0 takes most interrupts.
std::string pin_to_one_cpu()
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

const bench_stats *find(const std::vector<Row> &rows, const std::string &lib, const std::string &model,
                        const std::string &prec, const std::string &op)
{
    for (const Row &r : rows)
        if (r.lib == lib && r.model == model && r.prec == prec && r.op == op)
            return &r.s;
    return nullptr;
}

void target(const std::vector<Row> &rows, const char *lib, const char *op, double factor)
{
    const bench_stats *k = find(rows, "kinctl", "puma560", "double", op);
    const bench_stats *o = find(rows, lib, "puma560", "double", op);
    if (k == nullptr || o == nullptr) {
        std::printf("  %-4s %-10s >= %.1fx: not measured\n", op, lib, factor);
        return;
    }
    double ratio = o->median_ns / k->median_ns;
    // "Faster than" (factor 1) must be strictly faster.
    bool met = factor > 1.0 ? ratio >= factor : ratio > factor;
    std::printf("  %-4s %-10s %s %.1fx: %5.2fx  %s\n", op, lib, factor > 1.0 ? ">=" : "> ", factor, ratio,
                met ? "met" : "MISSED");
}

} // namespace

int main()
{
    std::printf("fk_bench: %d configurations per model, %d batches of %d calls (+%d warm-up), CLOCK_MONOTONIC\n",
                BENCH_CONFIGS, BENCH_BATCHES, BENCH_BATCH, BENCH_WARMUP);
    std::printf("%s\n", pin_to_one_cpu().c_str());
#ifndef KC_BENCH_WITH_PINOCCHIO
    std::printf("Pinocchio: not built: %s\n", KC_BENCH_PINOCCHIO_MISSING);
#endif

    HelperOutput dbl, flt;
    if (!run_helper(KC_BENCH_HELPER_DOUBLE, "double", dbl) || !run_helper(KC_BENCH_HELPER_FLOAT, "float", flt))
        return 1;

    std::vector<Row> rows = dbl.rows;
    rows.insert(rows.end(), flt.rows.begin(), flt.rows.end());
    double checksum = dbl.checksum + flt.checksum;
    bool all_ok = true;
    static double q[BENCH_CONFIGS][BENCH_MAX_JOINTS];
    static double ns[BENCH_BATCHES];

    for (int m = 0; m < BENCH_N_MODELS; m++) {
        const std::string name = bench_model_names[m];
        const Arm arm = m == BENCH_PUMA560 ? make_puma560() : make_panda();
        const int n = bench_model_joints[m];
        bench_make_configs(m, q);

        // Check first, on the first BENCH_CHECKS configurations.
        const KDL::Chain chain = kdl_chain(arm);
        std::vector<Result> kdl_ref;
        for (int k = 0; k < BENCH_CHECKS; k++)
            kdl_ref.push_back(kdl_eval(chain, q[k]));
        std::printf("check %s, max |difference| over %d configurations:\n", name.c_str(), BENCH_CHECKS);
        // Float is judged against double results for the unrounded q: its
        // error is q's rounding (6e-8 rad) and float arithmetic over a ~1 m arm.
        all_ok &= compare("kinctl double vs KDL", dbl.checks[name], kdl_ref, 1e-9);
        all_ok &= compare("kinctl float vs KDL", flt.checks[name], kdl_ref, 1e-5);
#ifdef KC_BENCH_WITH_PINOCCHIO
        const PinArm pin = pin_arm(arm);
        std::vector<Result> pin_ref;
        for (int k = 0; k < BENCH_CHECKS; k++)
            pin_ref.push_back(pin_eval(pin, q[k]));
        all_ok &= compare("kinctl double vs Pinocchio", dbl.checks[name], pin_ref, 1e-9);
        all_ok &= compare("KDL vs Pinocchio", kdl_ref, pin_ref, 1e-9);
#endif
        if (!all_ok)
            continue;

        // KDL: the solvers and outputs are made once, as a controller would.
        {
            std::vector<KDL::JntArray> qk(BENCH_CONFIGS, KDL::JntArray((unsigned)n));
            for (int k = 0; k < BENCH_CONFIGS; k++)
                for (int j = 0; j < n; j++)
                    qk[(size_t)k](j) = q[k][j];
            KDL::ChainFkSolverPos_recursive fk(chain);
            KDL::ChainJntToJacSolver js(chain);
            KDL::Frame f;
            KDL::Jacobian jac((unsigned)n);
            double sum = 0.0;
            BENCH_TIME(ns, fk.JntToCart(qk[(size_t)k], f); sum += f.p.x());
            rows.push_back(Row{"KDL", name, "double", "fk", bench_summarize(ns, BENCH_BATCHES)});
            BENCH_TIME(ns, js.JntToJac(qk[(size_t)k], jac); sum += jac(0, (unsigned)n - 1));
            rows.push_back(Row{"KDL", name, "double", "jac", bench_summarize(ns, BENCH_BATCHES)});
            checksum += sum;
        }
#ifdef KC_BENCH_WITH_PINOCCHIO
        // Pinocchio: FK is forwardKinematics (every joint placement) plus the
        // tool frame; the Jacobian call computes the placements it needs
        // itself, as kinctl's and KDL's do.
        {
            std::vector<Eigen::VectorXd> qv(BENCH_CONFIGS, Eigen::VectorXd(n));
            for (int k = 0; k < BENCH_CONFIGS; k++)
                for (int j = 0; j < n; j++)
                    qv[(size_t)k][j] = q[k][j];
            pinocchio::Data data(pin.model);
            pinocchio::Data::Matrix6x J = pinocchio::Data::Matrix6x::Zero(6, n);
            double sum = 0.0;
            BENCH_TIME(ns, pinocchio::forwardKinematics(pin.model, data, qv[(size_t)k]);
                       pinocchio::updateFramePlacement(pin.model, data, pin.tool);
                       sum += data.oMf[pin.tool].translation()[0]);
            rows.push_back(Row{"Pinocchio", name, "double", "fk", bench_summarize(ns, BENCH_BATCHES)});
            BENCH_TIME(ns, pinocchio::computeFrameJacobian(pin.model, data, qv[(size_t)k], pin.tool,
                                                           pinocchio::LOCAL_WORLD_ALIGNED, J);
                       sum += J(0, n - 1));
            rows.push_back(Row{"Pinocchio", name, "double", "jac", bench_summarize(ns, BENCH_BATCHES)});
            checksum += sum;
        }
#endif
    }
    if (!all_ok) {
        std::printf("libraries disagree: no timings printed\n");
        return 1;
    }

    std::printf("\nper call, ns; ratio = median / kinctl double median (same model and op): "
                "above 1 means kinctl double is faster\n");
    std::printf("%-10s %-8s %-6s %-4s %9s %9s %9s %7s\n", "library", "model", "prec", "op", "median", "p99", "max",
                "ratio");
    for (int m = 0; m < BENCH_N_MODELS; m++)
        for (const char *op : {"fk", "jac"})
            for (const Row &r : rows) {
                if (r.model != bench_model_names[m] || r.op != op)
                    continue;
                const bench_stats *base = find(rows, "kinctl", r.model, "double", r.op);
                std::printf("%-10s %-8s %-6s %-4s %9.1f %9.1f %9.1f %7.2f\n", r.lib.c_str(), r.model.c_str(),
                            r.prec.c_str(), r.op.c_str(), r.s.median_ns, r.s.p99_ns, r.s.max_ns,
                            r.s.median_ns / base->median_ns);
            }
    std::printf("\ntargets (puma560, double, ratio of medians):\n");
    target(rows, "KDL", "fk", 2.0);
    target(rows, "Pinocchio", "fk", 1.0);
    target(rows, "KDL", "jac", 4.0);
    target(rows, "Pinocchio", "jac", 1.5);
    std::printf("checksum %.17g\n", checksum);
    return 0;
}
