/* SPDX-License-Identifier: BSD-3-Clause */
// ik_bench.cpp - inverse kinematics: success rate and solve time of
// kinctl's kc_ik_solve beside Orocos KDL (ChainIkSolverPos_LMA,
// ChainIkSolverPos_NR_JL), Pinocchio's damped CLIK loop and the Robotics
// Toolbox's C++ ik_LM, on the same targets from the same starts; and the
// cost of one kc_ik_step (issue 3).
//
// The set (bench_common.h): per model BENCH_IK_TARGETS targets T = FK(q_true)
// with q_true uniform within the limits, a random start per target and one
// fixed start. The driver draws the joint vectors, has kinctl's double FK
// turn them into targets, checks those against KDL's and Pinocchio's FK
// (models of bench_models.hpp, written independently of kinctl's), and
// writes one file per model that the kinctl helpers and ik_bench_rtb.py
// read. kinctl runs in its helpers (one per precision), rtb in Python, KDL
// and Pinocchio here; every series solves its targets in BENCH_IK_ROUNDS
// blocks interleaved with the other libraries' blocks on the same targets,
// all pinned to one CPU (the machine's speed drifts).
//
// Nobody's word is taken for success: every returned q goes through
// kinctl's double FK and kc_chain_check_q (helper `fk`). Success is
// max |FK(q) - T| <= BENCH_IK_TOL over the 12 entries of [R | t]
// (vectors/ik.json's acceptance), "in limits" adds q within the position
// limits; a library that claims convergence and fails the check is counted.
//
// Usage: ik_bench <dir for the set files>; KC_BENCH_RTB="<python> <script>"
// adds rtb (KC_BENCH_RTB_NOTE says why when it is not there).

#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <kdl/chainfksolverpos_recursive.hpp>
#include <kdl/chainiksolverpos_lma.hpp>
#include <kdl/chainiksolverpos_nr_jl.hpp>
#include <kdl/chainiksolvervel_pinv.hpp>

#ifdef KC_BENCH_WITH_PINOCCHIO
#include <pinocchio/algorithm/frames.hpp>
#include <pinocchio/algorithm/jacobian.hpp>
#include <pinocchio/algorithm/joint-configuration.hpp>
#include <pinocchio/algorithm/kinematics.hpp>
#include <pinocchio/spatial.hpp>
#endif

#include "bench_common.h"
#include "bench_models.hpp"

namespace {

using namespace kcb;

constexpr int BLOCK = BENCH_IK_TARGETS / BENCH_IK_ROUNDS;
static_assert(BLOCK * BENCH_IK_ROUNDS == BENCH_IK_TARGETS, "BENCH_IK_ROUNDS must divide BENCH_IK_TARGETS");
constexpr int STEP_BLOCK = BENCH_STEP_RUNS / BENCH_IK_ROUNDS;

// Solver settings, stated in the output. KDL's eps is tight because both
// its solvers converge quadratically near the end (a tighter eps costs an
// iteration or so); LMA's is on its weighted error (default weights 1 for
// position, 0.01 for rotation: 1e-10 m, 1e-8 rad). Pinocchio's CLIK
// contracts the error by (1 - DT) per iteration, so every decade costs 22
// iterations: eps 1e-6 on |log6| is what the 1e-6 acceptance needs.
constexpr double KDL_LMA_EPS = 1e-10;
constexpr int KDL_LMA_MAXITER = 500; // KDL's default
constexpr double KDL_NRJL_EPS = 1e-10;
constexpr int KDL_NRJL_MAXITER = 100; // KDL's default
constexpr double PIN_EPS = 1e-6;
constexpr int PIN_IT_MAX = 1000;
constexpr double PIN_DT = 1e-1;
constexpr double PIN_DAMP = 1e-6;

struct Solve {
    double ns = NAN;
    bool claimed = false;
    int iters = -1;
    int restarts = 0;
    std::vector<double> q;
};

struct IkModel {
    int m;
    std::string name;
    unsigned n;
    std::string set_path;
    std::vector<std::array<double, 12>> T; // R row-major, t
    std::vector<std::vector<double>> q_start;
    std::vector<double> fixed;
};

// ---- the set ----

std::string write_q_file(const std::string &path, const std::vector<std::vector<double>> &qs)
{
    FILE *f = std::fopen(path.c_str(), "w");
    if (f == nullptr)
        return "cannot write " + path;
    for (const auto &q : qs) {
        for (double x : q)
            std::fprintf(f, " %.17g", x);
        std::fprintf(f, "\n");
    }
    std::fclose(f);
    return "";
}

// kinctl's double FK and limit check of each q: pose 12 numbers, then 1 if
// inside the limits (a NaN pose for a q kinctl rejects).
bool kinctl_fk(const std::string &model, const std::string &dir, const std::vector<std::vector<double>> &qs,
               std::vector<std::array<double, 13>> &poses)
{
    std::string path = dir + "/ik_q_" + model + ".txt", err = write_q_file(path, qs), out;
    if (!err.empty()) {
        std::printf("error: %s\n", err.c_str());
        return false;
    }
    if (!run_helper(KC_BENCH_HELPER_DOUBLE, "fk " + model + " " + path, out))
        return false;
    poses.clear();
    size_t pos = 0;
    for (size_t eol; (eol = out.find('\n', pos)) != std::string::npos; pos = eol + 1) {
        std::string line = out.substr(pos, eol - pos);
        std::array<double, 13> p;
        p.fill(NAN);
        std::vector<double> v = parse_numbers(line.c_str() + 5);
        if (line.compare(0, 5, "pose ") != 0 || (v.size() != 13 && line != "pose nan")) {
            std::printf("error: helper fk: %s\n", line.c_str());
            return false;
        }
        if (v.size() == 13)
            std::copy(v.begin(), v.end(), p.begin());
        poses.push_back(p);
    }
    if (poses.size() != qs.size()) {
        std::printf("error: helper fk gave %zu poses for %zu configurations\n", poses.size(), qs.size());
        return false;
    }
    return true;
}

bool make_set(int m, const std::string &dir, IkModel &im)
{
    static double q_true[BENCH_IK_TARGETS][BENCH_MAX_JOINTS], q_start[BENCH_IK_TARGETS][BENCH_MAX_JOINTS];
    double fixed[BENCH_MAX_JOINTS];
    im.m = m;
    im.name = bench_model_names[m];
    im.n = (unsigned)bench_model_joints[m];
    bench_make_ik_set(m, q_true, q_start);
    bench_ik_fixed_start(m, fixed);
    im.fixed.assign(fixed, fixed + im.n);
    std::vector<std::vector<double>> qt;
    for (int k = 0; k < BENCH_IK_TARGETS; k++) {
        qt.emplace_back(q_true[k], q_true[k] + im.n);
        im.q_start.emplace_back(q_start[k], q_start[k] + im.n);
    }
    std::vector<std::array<double, 13>> poses;
    if (!kinctl_fk(im.name, dir, qt, poses))
        return false;
    im.set_path = dir + "/ik_set_" + im.name + ".txt";
    FILE *f = std::fopen(im.set_path.c_str(), "w");
    if (f == nullptr) {
        std::printf("error: cannot write %s\n", im.set_path.c_str());
        return false;
    }
    std::fprintf(f, "%s %s %u %d\nfixed", BENCH_IK_SET_MAGIC, im.name.c_str(), im.n, BENCH_IK_TARGETS);
    for (double x : im.fixed)
        std::fprintf(f, " %.17g", x);
    std::fprintf(f, "\n");
    for (int k = 0; k < BENCH_IK_TARGETS; k++) {
        std::array<double, 12> T;
        std::copy(poses[(size_t)k].begin(), poses[(size_t)k].begin() + 12, T.begin());
        im.T.push_back(T);
        for (double x : T)
            std::fprintf(f, "%.17g ", x);
        for (double x : qt[(size_t)k])
            std::fprintf(f, "%.17g ", x);
        for (double x : im.q_start[(size_t)k])
            std::fprintf(f, " %.17g", x);
        std::fprintf(f, "\n");
    }
    std::fclose(f);
    return true;
}

// Reads `ik <k> <ns> <ok> <iters> <restarts> <q n>` lines into sol; other
// lines (rtb's notes) are handed to extra.
bool parse_ik_lines(const std::string &who, const std::string &out, unsigned n, int first, int count,
                    std::vector<Solve> &sol, const std::function<void(const std::string &)> &extra)
{
    int seen = 0;
    size_t pos = 0;
    for (size_t eol; (eol = out.find('\n', pos)) != std::string::npos; pos = eol + 1) {
        std::string line = out.substr(pos, eol - pos);
        if (line.compare(0, 3, "ik ") != 0) {
            extra(line);
            continue;
        }
        std::vector<double> v = parse_numbers(line.c_str() + 3);
        int k = v.empty() ? -1 : (int)v[0];
        if (v.size() != 5 + n || k < first || k >= first + count) {
            std::printf("error: %s: %s\n", who.c_str(), line.c_str());
            return false;
        }
        Solve &s = sol[(size_t)k];
        s.ns = v[1];
        s.claimed = v[2] != 0.0;
        s.iters = (int)v[3];
        s.restarts = (int)v[4];
        s.q.assign(v.begin() + 5, v.end());
        seen++;
    }
    if (seen != count) {
        std::printf("error: %s gave %d solutions, not %d:\n%s\n", who.c_str(), seen, count, out.c_str());
        return false;
    }
    return true;
}

// ---- Orocos KDL ----

// NR_JL does not report its iterations; each one evaluates FK once, so a
// counting FK solver tells them.
class CountingFk : public KDL::ChainFkSolverPos_recursive {
  public:
    explicit CountingFk(const KDL::Chain &chain) : KDL::ChainFkSolverPos_recursive(chain) {}
    using KDL::ChainFkSolverPos_recursive::JntToCart;
    int JntToCart(const KDL::JntArray &q, KDL::Frame &p, int segment = -1) override
    {
        calls++;
        return KDL::ChainFkSolverPos_recursive::JntToCart(q, p, segment);
    }
    int calls = 0;
};

// Solvers are made once, outside the timed loop, as a controller would.
// Held by pointer: the solvers keep references to chain and each other.
struct KdlIk {
    KDL::Chain chain;
    KDL::JntArray q_min, q_max, q0, q_out;
    std::vector<KDL::Frame> T;
    std::unique_ptr<KDL::ChainIkSolverPos_LMA> lma;
    std::unique_ptr<CountingFk> fk;
    std::unique_ptr<KDL::ChainIkSolverVel_pinv> vel;
    std::unique_ptr<KDL::ChainIkSolverPos_NR_JL> nr_jl;
};

std::unique_ptr<KdlIk> make_kdl(const IkModel &im, const Arm &arm)
{
    auto k = std::make_unique<KdlIk>();
    k->chain = kdl_chain(arm);
    k->q_min.resize(im.n);
    k->q_max.resize(im.n);
    k->q0.resize(im.n);
    k->q_out.resize(im.n);
    for (unsigned j = 0; j < im.n; j++) {
        k->q_min(j) = bench_qlim[im.m][j][0];
        k->q_max(j) = bench_qlim[im.m][j][1];
    }
    for (const auto &t : im.T)
        k->T.emplace_back(KDL::Rotation(t[0], t[1], t[2], t[3], t[4], t[5], t[6], t[7], t[8]),
                          KDL::Vector(t[9], t[10], t[11]));
    k->lma = std::make_unique<KDL::ChainIkSolverPos_LMA>(k->chain, KDL_LMA_EPS, KDL_LMA_MAXITER);
    k->fk = std::make_unique<CountingFk>(k->chain);
    k->vel = std::make_unique<KDL::ChainIkSolverVel_pinv>(k->chain);
    k->nr_jl = std::make_unique<KDL::ChainIkSolverPos_NR_JL>(k->chain, k->q_min, k->q_max, *k->fk, *k->vel,
                                                             KDL_NRJL_MAXITER, KDL_NRJL_EPS);
    return k;
}

// ---- Pinocchio: the damped CLIK loop of its inverse-kinematics example,
// on the tool frame, with one kinematics pass per iteration. It knows no
// joint limits. ----

#ifdef KC_BENCH_WITH_PINOCCHIO
struct PinIk {
    PinArm arm;
    std::unique_ptr<pinocchio::Data> data;
    pinocchio::Data::Matrix6x J;
    Eigen::VectorXd q, v, q_next;
    std::vector<pinocchio::SE3> T;
};

std::unique_ptr<PinIk> make_pin(const IkModel &im, const Arm &arm)
{
    auto p = std::make_unique<PinIk>();
    p->arm = pin_arm(arm);
    p->data = std::make_unique<pinocchio::Data>(p->arm.model);
    p->J = pinocchio::Data::Matrix6x::Zero(6, im.n);
    p->q = p->v = p->q_next = Eigen::VectorXd::Zero(im.n);
    for (const auto &t : im.T) {
        Eigen::Matrix3d R;
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++)
                R(i, j) = t[(size_t)(3 * i + j)];
        p->T.emplace_back(R, Eigen::Vector3d(t[9], t[10], t[11]));
    }
    return p;
}

// From p.q; returns the iterations, negative when IT_MAX was reached.
int pin_clik(PinIk &p, const pinocchio::SE3 &oMdes)
{
    const pinocchio::Model &model = p.arm.model;
    pinocchio::Data &data = *p.data;
    Eigen::Matrix<double, 6, 1> err;
    Eigen::Matrix<double, 6, 6> JJt;
    for (int i = 0;; i++) {
        pinocchio::computeJointJacobians(model, data, p.q);
        pinocchio::updateFramePlacement(model, data, p.arm.tool);
        err = pinocchio::log6(oMdes.actInv(data.oMf[p.arm.tool])).toVector();
        if (err.norm() < PIN_EPS)
            return i;
        if (i >= PIN_IT_MAX)
            return -i;
        pinocchio::getFrameJacobian(model, data, p.arm.tool, pinocchio::LOCAL, p.J);
        JJt.noalias() = p.J * p.J.transpose();
        JJt.diagonal().array() += PIN_DAMP;
        p.v.noalias() = -p.J.transpose() * JJt.ldlt().solve(err);
        pinocchio::integrate(model, p.q, p.v * PIN_DT, p.q_next);
        p.q.swap(p.q_next);
    }
}
#endif

// ---- series and statistics ----

struct Series {
    std::string lib, model, start, prec;
    // Solves targets first..first+count-1 into sol.
    std::function<bool(int first, int count, std::vector<Solve> &sol)> block;
    std::vector<Solve> sol = std::vector<Solve>(BENCH_IK_TARGETS);
    // kinctl: how often each non-converged status came back (shared with
    // the block function, which outlives no Series but is copied with it).
    std::shared_ptr<std::map<std::string, int>> statuses = std::make_shared<std::map<std::string, int>>();
    int ok = 0, ok_lim = 0, false_claims = 0, restarted = 0;
    long restarts = 0;
    double mean_iters = NAN, worst_err = 0.0;
    bench_stats s{};
};

bool judge(Series &se, const IkModel &im, const std::string &dir)
{
    std::vector<std::vector<double>> qs;
    for (const Solve &s : se.sol)
        qs.push_back(s.q.size() == im.n ? s.q : std::vector<double>(im.n, NAN));
    std::vector<std::array<double, 13>> poses;
    if (!kinctl_fk(im.name, dir, qs, poses))
        return false;
    std::vector<double> ns;
    double iters = 0.0;
    int n_iters = 0;
    for (int k = 0; k < BENCH_IK_TARGETS; k++) {
        const Solve &s = se.sol[(size_t)k];
        double err = 0.0;
        for (int i = 0; i < 12; i++)
            err = std::fmax(err, std::fabs(poses[(size_t)k][(size_t)i] - im.T[(size_t)k][(size_t)i]));
        if (std::isnan(poses[(size_t)k][0]))
            err = INFINITY;
        bool ok = err <= BENCH_IK_TOL;
        se.ok += ok;
        se.ok_lim += ok && poses[(size_t)k][12] == 1.0;
        se.false_claims += s.claimed && !ok;
        if (ok)
            se.worst_err = std::fmax(se.worst_err, err);
        se.restarts += s.restarts;
        se.restarted += s.restarts > 0;
        if (s.iters >= 0) {
            iters += s.iters;
            n_iters++;
        }
        ns.push_back(s.ns);
    }
    if (n_iters == BENCH_IK_TARGETS)
        se.mean_iters = iters / n_iters;
    se.s = bench_summarize(ns.data(), (int)ns.size());
    return true;
}

struct StepSeries {
    std::string model, prec;
    const char *helper;
    std::string set_path;
    std::vector<double> ns;
    int done = 0;
    bench_stats s{};
};

bool step_block(StepSeries &ss, int first)
{
    std::string out;
    if (!run_helper(ss.helper, "step " + ss.model + " " + ss.set_path + " " + std::to_string(first) + " " +
                                   std::to_string(STEP_BLOCK), out))
        return false;
    size_t done_at = out.find("\ndone ");
    if (out.compare(0, 3, "ns ") != 0 || done_at == std::string::npos) {
        std::printf("error: helper step: %s\n", out.c_str());
        return false;
    }
    std::vector<double> v = parse_numbers(out.c_str() + 3);
    ss.ns.insert(ss.ns.end(), v.begin(), v.end());
    ss.done += std::atoi(out.c_str() + done_at + 6);
    return true;
}

// Median cost of reading the clock, which every per-solve time includes.
double timer_overhead_ns()
{
    std::vector<double> d;
    for (int i = 0; i < 10001; i++) {
        double t0 = bench_now_ns(), t1 = bench_now_ns();
        d.push_back(t1 - t0);
    }
    return bench_summarize(d.data(), (int)d.size()).median_ns;
}

} // namespace

int main(int argc, char **argv)
{
    if (argc != 2) {
        std::printf("usage: %s <directory for the IK set files>\n", argv[0]);
        return 2;
    }
    const std::string dir = argv[1];
    const char *rtb = std::getenv("KC_BENCH_RTB");
    const char *rtb_note = std::getenv("KC_BENCH_RTB_NOTE");
    std::printf("ik_bench: %d targets per model, fixed and random starts, %d interleaved rounds; success = "
                "max |FK(q) - T| <= %.0e over the 12 entries (kinctl's double FK)\n",
                BENCH_IK_TARGETS, BENCH_IK_ROUNDS, BENCH_IK_TOL);
    std::printf("%s; clock read %.0f ns (included in every time)\n", pin_to_one_cpu().c_str(), timer_overhead_ns());
    std::printf("fixed start: puma560 rtb qn (0 45 -180 0 45 0 deg); panda the middle of every joint's range\n");
    std::printf("kinctl: kc_ik_cfg_default() (restarts counted); KDL LMA eps %.0e (weighted) maxiter %d, "
                "NR_JL + ChainIkSolverVel_pinv eps %.0e maxiter %d; Pinocchio CLIK DT %.1f damp %.0e eps %.0e "
                "IT_MAX %d (no joint limits)\n",
                KDL_LMA_EPS, KDL_LMA_MAXITER, KDL_NRJL_EPS, KDL_NRJL_MAXITER, PIN_DT, PIN_DAMP, PIN_EPS, PIN_IT_MAX);
#ifndef KC_BENCH_WITH_PINOCCHIO
    std::printf("Pinocchio: not built: %s\n", KC_BENCH_PINOCCHIO_MISSING);
#endif
    if (rtb == nullptr || *rtb == '\0')
        std::printf("rtb: not run: %s\n", rtb_note != nullptr && *rtb_note ? rtb_note : "KC_BENCH_RTB not set");

    std::vector<IkModel> models(BENCH_N_MODELS);
    std::vector<std::unique_ptr<KdlIk>> kdl;
#ifdef KC_BENCH_WITH_PINOCCHIO
    std::vector<std::unique_ptr<PinIk>> pin;
#endif
    bool rtb_ok = rtb != nullptr && *rtb != '\0';
    for (int m = 0; m < BENCH_N_MODELS; m++) {
        IkModel &im = models[(size_t)m];
        if (!make_set(m, dir, im))
            return 1;
        const Arm arm = m == BENCH_PUMA560 ? make_puma560() : make_panda();
        kdl.push_back(make_kdl(im, arm));
        // The targets are kinctl's FK; the other libraries must agree that
        // they are the poses of q_true, or they would solve other problems.
        static double q_true[BENCH_IK_TARGETS][BENCH_MAX_JOINTS], q_start[BENCH_IK_TARGETS][BENCH_MAX_JOINTS];
        bench_make_ik_set(m, q_true, q_start);
        KDL::ChainFkSolverPos_recursive fk(kdl.back()->chain);
        double d_kdl = 0.0;
        for (int k = 0; k < BENCH_IK_TARGETS; k++) {
            KDL::JntArray q(im.n);
            KDL::Frame f;
            for (unsigned j = 0; j < im.n; j++)
                q(j) = q_true[k][j];
            fk.JntToCart(q, f);
            for (int i = 0; i < 3; i++) {
                for (int j = 0; j < 3; j++)
                    d_kdl = std::fmax(d_kdl, std::fabs(f.M(i, j) - im.T[(size_t)k][(size_t)(3 * i + j)]));
                d_kdl = std::fmax(d_kdl, std::fabs(f.p(i) - im.T[(size_t)k][(size_t)(9 + i)]));
            }
        }
        std::printf("check %s targets: kinctl FK vs KDL max |difference| %.1e", im.name.c_str(), d_kdl);
        bool ok = d_kdl <= 1e-9;
#ifdef KC_BENCH_WITH_PINOCCHIO
        pin.push_back(make_pin(im, arm));
        double d_pin = 0.0;
        for (int k = 0; k < BENCH_IK_TARGETS; k++) {
            PinIk &p = *pin.back();
            for (unsigned j = 0; j < im.n; j++)
                p.q[j] = q_true[k][j];
            pinocchio::forwardKinematics(p.arm.model, *p.data, p.q);
            pinocchio::updateFramePlacement(p.arm.model, *p.data, p.arm.tool);
            d_pin = std::fmax(d_pin, (p.data->oMf[p.arm.tool].toHomogeneousMatrix() -
                                      p.T[(size_t)k].toHomogeneousMatrix())
                                         .cwiseAbs()
                                         .maxCoeff());
        }
        std::printf(", vs Pinocchio %.1e", d_pin);
        ok &= d_pin <= 1e-9;
#endif
        if (rtb_ok) {
            std::string out;
            rtb_ok = run_helper(rtb, "check " + im.set_path, out);
            std::printf(", vs rtb %s", rtb_ok ? out.substr(0, out.find('\n')).c_str() : "(failed)");
        }
        std::printf("\n");
        if (!ok) {
            std::printf("libraries disagree on the targets: nothing timed\n");
            return 1;
        }
    }
    if (rtb != nullptr && *rtb != '\0' && !rtb_ok)
        std::printf("rtb: left out: its check failed (output above)\n");

    // ---- the series, grouped by model and start ----
    std::vector<Series> rows;
    std::vector<std::string> rtb_notes;
    size_t group = 0;
    for (int m = 0; m < BENCH_N_MODELS; m++) {
        IkModel *im = &models[(size_t)m];
        for (const std::string start : {"fixed", "random"}) {
            const bool fixed = start == "fixed";
            size_t first_row = rows.size();
            for (const char *prec : {"double", "float"}) {
                const char *path = std::strcmp(prec, "double") == 0 ? KC_BENCH_HELPER_DOUBLE : KC_BENCH_HELPER_FLOAT;
                auto statuses = std::make_shared<std::map<std::string, int>>();
                rows.push_back(Series{"kinctl", im->name, start, prec,
                                      [=](int first, int count, std::vector<Solve> &sol) {
                                          std::string out;
                                          return run_helper(path,
                                                            "ik " + im->name + " " + im->set_path + " " + start +
                                                                " " + std::to_string(first) + " " +
                                                                std::to_string(count),
                                                            out) &&
                                                 parse_ik_lines(path, out, im->n, first, count, sol,
                                                                [=](const std::string &l) {
                                                                    // "status <k> <text>"
                                                                    size_t sp = l.find(' ', 7);
                                                                    (*statuses)[l.substr(sp + 1)]++;
                                                                });
                                      }});
                rows.back().statuses = statuses;
            }
            KdlIk *kc = kdl[(size_t)m].get();
            // One KDL solve, timed or not; iterations as the solver counts them.
            auto kdl_solve = [=](bool lma, int k, Solve *out) {
                const std::vector<double> &q0 = fixed ? im->fixed : im->q_start[(size_t)k];
                for (unsigned j = 0; j < im->n; j++)
                    kc->q0(j) = q0[j];
                kc->fk->calls = 0;
                double t0 = bench_now_ns();
                int rc = lma ? kc->lma->CartToJnt(kc->q0, kc->T[(size_t)k], kc->q_out)
                             : kc->nr_jl->CartToJnt(kc->q0, kc->T[(size_t)k], kc->q_out);
                double t1 = bench_now_ns();
                if (out == nullptr)
                    return;
                out->ns = t1 - t0;
                out->claimed = rc >= 0;
                out->iters = lma ? kc->lma->lastNrOfIter : kc->fk->calls;
                out->q.assign(kc->q_out.data.data(), kc->q_out.data.data() + im->n);
            };
            for (bool lma : {true, false})
                rows.push_back(Series{lma ? "KDL LMA" : "KDL NR_JL", im->name, start, "double",
                                      [=](int first, int count, std::vector<Solve> &sol) {
                                          for (int k = first; k < first + BENCH_IK_WARMUP; k++)
                                              kdl_solve(lma, k, nullptr);
                                          for (int k = first; k < first + count; k++)
                                              kdl_solve(lma, k, &sol[(size_t)k]);
                                          return true;
                                      }});
#ifdef KC_BENCH_WITH_PINOCCHIO
            PinIk *pc = pin[(size_t)m].get();
            auto pin_solve = [=](int k, Solve *out) {
                const std::vector<double> &q0 = fixed ? im->fixed : im->q_start[(size_t)k];
                for (unsigned j = 0; j < im->n; j++)
                    pc->q[j] = q0[j];
                double t0 = bench_now_ns();
                int it = pin_clik(*pc, pc->T[(size_t)k]);
                double t1 = bench_now_ns();
                if (out == nullptr)
                    return;
                out->ns = t1 - t0;
                out->claimed = it >= 0;
                out->iters = std::abs(it);
                out->q.assign(pc->q.data(), pc->q.data() + im->n);
            };
            rows.push_back(Series{"Pinocchio CLIK", im->name, start, "double",
                                  [=](int first, int count, std::vector<Solve> &sol) {
                                      for (int k = first; k < first + BENCH_IK_WARMUP; k++)
                                          pin_solve(k, nullptr);
                                      for (int k = first; k < first + count; k++)
                                          pin_solve(k, &sol[(size_t)k]);
                                      return true;
                                  }});
#endif
            if (rtb_ok) {
                std::vector<std::string> *notes = &rtb_notes;
                std::string label = im->name + " " + start;
                rows.push_back(Series{"rtb ik_LM", im->name, start, "double",
                                      [=](int first, int count, std::vector<Solve> &sol) {
                                          std::string out;
                                          return run_helper(rtb,
                                                            "ik " + im->set_path + " " + start + " " +
                                                                std::to_string(first) + " " + std::to_string(count),
                                                            out) &&
                                                 parse_ik_lines("rtb", out, im->n, first, count, sol,
                                                                [=](const std::string &l) {
                                                                    notes->push_back(label + ": " + l);
                                                                });
                                      }});
            }
            group = rows.size() - first_row;
        }
    }

    std::vector<StepSeries> steps;
    for (const IkModel &im : models)
        for (const char *prec : {"double", "float"})
            steps.push_back(StepSeries{im.name, prec,
                                       std::strcmp(prec, "double") == 0 ? KC_BENCH_HELPER_DOUBLE
                                                                        : KC_BENCH_HELPER_FLOAT,
                                       im.set_path, {}, 0, {}});

    // ---- interleaved rounds; the first library of a group rotates each
    // round so none always follows the same other ----
    for (int r = 0; r < BENCH_IK_ROUNDS; r++) {
        for (size_t g = 0; g < rows.size(); g += group)
            for (size_t i = 0; i < group; i++) {
                Series &s = rows[g + (i + (size_t)r) % group];
                if (!s.block(r * BLOCK, BLOCK, s.sol))
                    return 1;
            }
        for (size_t i = 0; i < steps.size(); i++)
            if (!step_block(steps[(i + (size_t)r) % steps.size()], r * STEP_BLOCK))
                return 1;
        std::fprintf(stderr, "ik_bench: round %d of %d done\n", r + 1, BENCH_IK_ROUNDS);
    }
    for (Series &s : rows)
        if (!judge(s, models[s.model == "puma560" ? 0 : 1], dir))
            return 1;
    for (StepSeries &s : steps)
        s.s = bench_summarize(s.ns.data(), (int)s.ns.size());

    // ---- the table ----
    std::printf("\nper solve, us (all %d solves, failures included); iterations as each library counts them "
                "(kinctl: Jacobians over all attempts; NR_JL: FK evaluations); restarts: total (solves that "
                "needed any)\n",
                BENCH_IK_TARGETS);
    std::printf("%-15s %-8s %-6s %-6s %8s %8s %8s %8s %9s %7s %12s\n", "library", "model", "start", "prec",
                "success", "in-lim", "median", "p99", "max", "iter", "restarts");
    for (const Series &r : rows) {
        char iters[16] = "-", restarts[32] = "-";
        if (!std::isnan(r.mean_iters))
            std::snprintf(iters, sizeof iters, "%.1f", r.mean_iters);
        if (r.lib == "kinctl" || r.lib == "rtb ik_LM")
            std::snprintf(restarts, sizeof restarts, "%ld (%d)", r.restarts, r.restarted);
        std::printf("%-15s %-8s %-6s %-6s %7.1f%% %7.1f%% %8.1f %8.1f %9.1f %7s %12s\n", r.lib.c_str(),
                    r.model.c_str(), r.start.c_str(), r.prec.c_str(), 100.0 * r.ok / BENCH_IK_TARGETS,
                    100.0 * r.ok_lim / BENCH_IK_TARGETS, r.s.median_ns / 1e3, r.s.p99_ns / 1e3, r.s.max_ns / 1e3,
                    iters, restarts);
    }
    for (const Series &r : rows)
        for (const auto &st : *r.statuses)
            std::printf("  %s %s %s %s: kc_ik_solve returned \"%s\" %d times\n", r.lib.c_str(), r.model.c_str(),
                        r.start.c_str(), r.prec.c_str(), st.first.c_str(), st.second);
    // Float kinctl converges to its own float tolerances (1e-5 m, 1e-4 rad),
    // coarser than the acceptance: its claims are not false, only looser.
    for (const Series &r : rows)
        if (r.false_claims > 0)
            std::printf("  %s %s %s %s: %d solves %s\n", r.lib.c_str(), r.model.c_str(), r.start.c_str(),
                        r.prec.c_str(), r.false_claims,
                        r.prec == "float" ? "converged to float tolerances but missed the 1e-6 acceptance"
                                          : "claimed convergence and failed the FK check");
    if (!rtb_notes.empty()) {
        // The script's Python-overhead estimate, one line per block.
        std::vector<double> ov;
        for (const std::string &l : rtb_notes) {
            size_t at = l.find("overhead ");
            if (at != std::string::npos)
                ov.push_back(std::strtod(l.c_str() + at + 9, nullptr));
        }
        if (!ov.empty())
            std::printf("  rtb ik_LM times include the Python call (ETS.ik_LM from Python, perf_counter_ns): "
                        "ik_LM started at the solution (0-1 iterations) takes %.1f us median\n",
                        bench_summarize(ov.data(), (int)ov.size()).median_ns / 1e3);
    }

    std::printf("\nkc_ik_step per call, ns (%d runs from the random starts towards the targets, at most %d "
                "cycles of %.0f ms each, every call timed)\n",
                BENCH_STEP_RUNS, BENCH_STEP_CYCLES, BENCH_STEP_DT * 1e3);
    std::printf("%-8s %-6s %8s %8s %8s %8s %6s\n", "model", "prec", "calls", "median", "p99", "max", "done");
    for (const StepSeries &s : steps)
        std::printf("%-8s %-6s %8zu %8.0f %8.0f %8.0f %6d\n", s.model.c_str(), s.prec.c_str(), s.ns.size(),
                    s.s.median_ns, s.s.p99_ns, s.s.max_ns, s.done);

    std::printf("\ntargets (kinctl double, random starts): success in limits >= 99.9%%, median <= 10 us (puma560) "
                "/ 15 us (panda), p99 <= 100 us\n");
    for (const Series &r : rows) {
        if (r.lib != "kinctl" || r.prec != "double" || r.start != "random")
            continue;
        double med_max = r.model == "puma560" ? 10.0 : 15.0, pct = 100.0 * r.ok_lim / BENCH_IK_TARGETS;
        bool a = pct >= 99.9, b = r.s.median_ns / 1e3 <= med_max, c = r.s.p99_ns / 1e3 <= 100.0;
        std::printf("  %-8s success in limits %5.1f%% %s, median %6.1f us %s, p99 %6.1f us %s\n", r.model.c_str(),
                    pct, a ? "met" : "MISSED", r.s.median_ns / 1e3, b ? "met" : "MISSED", r.s.p99_ns / 1e3,
                    c ? "met" : "MISSED");
    }
    return 0;
}
