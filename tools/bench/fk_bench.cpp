/* SPDX-License-Identifier: BSD-3-Clause */
// fk_bench.cpp - FK and Jacobian time per call: kinctl against Orocos KDL and
// Pinocchio on the same DH tables and the same configurations (issue 2).
//
// kinctl's double and float builds share symbol names, so each is timed by
// its own helper executable (kinctl_helper.c) that this driver runs; KDL and
// Pinocchio are timed here, in the same invocation and pinned to the same CPU
// (children inherit the affinity). Every series is timed in BENCH_ROUNDS
// blocks interleaved with the others' (see bench_common.h: the machine's
// speed drifts). Before any timing every library is checked against the
// others on the first BENCH_CHECKS configurations: a benchmark of a wrong
// computation is worthless, so a mismatch stops it.
//
// The KDL and Pinocchio models are those of bench_models.hpp, written
// independently of kinctl's own model builders, so the check also tests
// kinctl's built-in models.

#include <sched.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <map>
#include <memory>
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
#include "bench_models.hpp"

namespace {

using namespace kcb;

// Pose as R row-major then t, and Jacobian as 6 x n row-major (vx vy vz wx
// wy wz): the helpers' order.
struct Result {
    std::vector<double> pose, jac;
};

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

#ifdef KC_BENCH_WITH_PINOCCHIO
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

// Results of `helper check`, by model then configuration.
bool helper_checks(const char *path, std::map<std::string, std::vector<Result>> &checks)
{
    std::string out;
    if (!run_helper(path, "check", out))
        return false;
    size_t pos = 0;
    for (size_t eol; (eol = out.find('\n', pos)) != std::string::npos; pos = eol + 1) {
        std::string line = out.substr(pos, eol - pos);
        char model[32], what[8];
        int idx, used = 0;
        if (std::sscanf(line.c_str(), "check %31s %d %7s %n", model, &idx, what, &used) != 3 || used == 0 ||
            idx < 0 || idx >= BENCH_CHECKS) {
            std::printf("error: %s check: %s\n", path, line.c_str());
            return false;
        }
        std::vector<Result> &v = checks[model];
        v.resize(BENCH_CHECKS);
        (std::strcmp(what, "pose") == 0 ? v[(size_t)idx].pose : v[(size_t)idx].jac) =
            parse_numbers(line.c_str() + used);
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

// ---- timing ----

// One row of the table: a library, model, precision and operation, and a
// block function that times BENCH_BATCHES_PER_ROUND batches into ns.
struct Series {
    std::string lib, model, prec, op;
    std::function<bool(std::vector<double> &ns, double &checksum)> block;
    std::vector<double> ns;
    bench_stats s;
};

// Solvers and outputs are made once, outside the timed loop, as a
// controller would. Held by pointer: the solvers keep references to chain.
struct KdlCtx {
    KDL::Chain chain;
    std::vector<KDL::JntArray> q;
    std::unique_ptr<KDL::ChainFkSolverPos_recursive> fk;
    std::unique_ptr<KDL::ChainJntToJacSolver> js;
    KDL::Frame f;
    KDL::Jacobian jac;
    std::vector<double> ns_block = std::vector<double>(BENCH_BATCHES_PER_ROUND);
};

#ifdef KC_BENCH_WITH_PINOCCHIO
struct PinCtx {
    PinArm arm;
    std::unique_ptr<pinocchio::Data> data;
    pinocchio::Data::Matrix6x J;
    std::vector<Eigen::VectorXd> q;
    std::vector<double> ns_block = std::vector<double>(BENCH_BATCHES_PER_ROUND);
};
#endif

const bench_stats *find(const std::vector<Series> &rows, const std::string &lib, const std::string &model,
                        const std::string &prec, const std::string &op)
{
    for (const Series &r : rows)
        if (r.lib == lib && r.model == model && r.prec == prec && r.op == op)
            return &r.s;
    return nullptr;
}

void target(const std::vector<Series> &rows, const char *lib, const char *op, double factor)
{
    const bench_stats *k = find(rows, "kinctl", "puma560", "double", op);
    const bench_stats *o = find(rows, lib, "puma560", "double", op);
    if (k == nullptr || o == nullptr) {
        std::printf("  %-4s %-10s %.1fx: not measured\n", op, lib, factor);
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
    std::printf("fk_bench: %d configurations per model; per series %d rounds x %d batches of %d calls "
                "(+%d warm-up batches a round), CLOCK_MONOTONIC\n",
                BENCH_CONFIGS, BENCH_ROUNDS, BENCH_BATCHES_PER_ROUND, BENCH_BATCH, BENCH_WARMUP);
    std::printf("%s\n", pin_to_one_cpu().c_str());
#ifndef KC_BENCH_WITH_PINOCCHIO
    std::printf("Pinocchio: not built: %s\n", KC_BENCH_PINOCCHIO_MISSING);
#endif

    // ---- check that everyone computes the same thing ----
    std::map<std::string, std::vector<Result>> dbl, flt;
    if (!helper_checks(KC_BENCH_HELPER_DOUBLE, dbl) || !helper_checks(KC_BENCH_HELPER_FLOAT, flt))
        return 1;
    bool all_ok = true;
    static double q[BENCH_N_MODELS][BENCH_CONFIGS][BENCH_MAX_JOINTS];
    std::vector<std::unique_ptr<KdlCtx>> kdl;
#ifdef KC_BENCH_WITH_PINOCCHIO
    std::vector<std::unique_ptr<PinCtx>> pin;
#endif
    for (int m = 0; m < BENCH_N_MODELS; m++) {
        const std::string name = bench_model_names[m];
        const Arm arm = m == BENCH_PUMA560 ? make_puma560() : make_panda();
        const unsigned n = (unsigned)bench_model_joints[m];
        bench_make_configs(m, q[m]);

        kdl.push_back(std::make_unique<KdlCtx>());
        KdlCtx &kc = *kdl.back();
        kc.chain = kdl_chain(arm);
        std::vector<Result> kdl_ref;
        for (int k = 0; k < BENCH_CHECKS; k++)
            kdl_ref.push_back(kdl_eval(kc.chain, q[m][k]));
        std::printf("check %s, max |difference| over %d configurations:\n", name.c_str(), BENCH_CHECKS);
        // Float is judged against double results for the unrounded q: its
        // error is q's rounding (6e-8 rad) and float arithmetic over a ~1 m arm.
        all_ok &= compare("kinctl double vs KDL", dbl[name], kdl_ref, 1e-9);
        all_ok &= compare("kinctl float vs KDL", flt[name], kdl_ref, 1e-5);
        kc.q.assign(BENCH_CONFIGS, KDL::JntArray(n));
        for (int k = 0; k < BENCH_CONFIGS; k++)
            for (unsigned j = 0; j < n; j++)
                kc.q[(size_t)k](j) = q[m][k][j];
        kc.fk = std::make_unique<KDL::ChainFkSolverPos_recursive>(kc.chain);
        kc.js = std::make_unique<KDL::ChainJntToJacSolver>(kc.chain);
        kc.jac.resize(n);
#ifdef KC_BENCH_WITH_PINOCCHIO
        pin.push_back(std::make_unique<PinCtx>());
        PinCtx &pc = *pin.back();
        pc.arm = pin_arm(arm);
        std::vector<Result> pin_ref;
        for (int k = 0; k < BENCH_CHECKS; k++)
            pin_ref.push_back(pin_eval(pc.arm, q[m][k]));
        all_ok &= compare("kinctl double vs Pinocchio", dbl[name], pin_ref, 1e-9);
        all_ok &= compare("KDL vs Pinocchio", kdl_ref, pin_ref, 1e-9);
        pc.data = std::make_unique<pinocchio::Data>(pc.arm.model);
        pc.J = pinocchio::Data::Matrix6x::Zero(6, n);
        pc.q.assign(BENCH_CONFIGS, Eigen::VectorXd((Eigen::Index)n));
        for (int k = 0; k < BENCH_CONFIGS; k++)
            for (unsigned j = 0; j < n; j++)
                pc.q[(size_t)k][j] = q[m][k][j];
#endif
    }
    if (!all_ok) {
        std::printf("libraries disagree: nothing timed\n");
        return 1;
    }

    // ---- the series, grouped by model and operation ----
    std::vector<Series> rows;
    size_t group = 0;
    for (int m = 0; m < BENCH_N_MODELS; m++) {
        const std::string name = bench_model_names[m];
        const int last = bench_model_joints[m] - 1;
        KdlCtx *kc = kdl[(size_t)m].get();
        for (const std::string op : {"fk", "jac"}) {
            size_t first = rows.size();
            for (const char *prec : {"double", "float"}) {
                const char *path = std::strcmp(prec, "double") == 0 ? KC_BENCH_HELPER_DOUBLE : KC_BENCH_HELPER_FLOAT;
                rows.push_back(Series{"kinctl", name, prec, op, [=](std::vector<double> &ns, double &sum) {
                                          return helper_block(path, name + " " + op, BENCH_BATCHES_PER_ROUND, ns, sum);
                                      }, {}, {}});
            }
            // The checksum reads one output of every call, so no call can be
            // dropped as dead code; it costs one add per call, as in the helpers.
            if (op == "fk")
                rows.push_back(Series{"KDL", name, "double", op, [=](std::vector<double> &ns, double &sum) {
                                          BENCH_TIME(kc->ns_block, BENCH_BATCHES_PER_ROUND,
                                                     kc->fk->JntToCart(kc->q[(size_t)k], kc->f); sum += kc->f.p.x());
                                          ns.insert(ns.end(), kc->ns_block.begin(), kc->ns_block.end());
                                          return true;
                                      }, {}, {}});
            else
                rows.push_back(Series{"KDL", name, "double", op, [=](std::vector<double> &ns, double &sum) {
                                          BENCH_TIME(kc->ns_block, BENCH_BATCHES_PER_ROUND,
                                                     kc->js->JntToJac(kc->q[(size_t)k], kc->jac);
                                                     sum += kc->jac(0, (unsigned)last));
                                          ns.insert(ns.end(), kc->ns_block.begin(), kc->ns_block.end());
                                          return true;
                                      }, {}, {}});
#ifdef KC_BENCH_WITH_PINOCCHIO
            // FK is forwardKinematics (every joint placement) plus the tool
            // frame; the Jacobian call computes the placements it needs
            // itself, as kinctl's and KDL's do.
            PinCtx *pc = pin[(size_t)m].get();
            if (op == "fk")
                rows.push_back(Series{"Pinocchio", name, "double", op, [=](std::vector<double> &ns, double &sum) {
                                          BENCH_TIME(pc->ns_block, BENCH_BATCHES_PER_ROUND,
                                                     pinocchio::forwardKinematics(pc->arm.model, *pc->data,
                                                                                  pc->q[(size_t)k]);
                                                     pinocchio::updateFramePlacement(pc->arm.model, *pc->data,
                                                                                     pc->arm.tool);
                                                     sum += pc->data->oMf[pc->arm.tool].translation()[0]);
                                          ns.insert(ns.end(), pc->ns_block.begin(), pc->ns_block.end());
                                          return true;
                                      }, {}, {}});
            else
                rows.push_back(Series{"Pinocchio", name, "double", op, [=](std::vector<double> &ns, double &sum) {
                                          BENCH_TIME(pc->ns_block, BENCH_BATCHES_PER_ROUND,
                                                     pinocchio::computeFrameJacobian(
                                                         pc->arm.model, *pc->data, pc->q[(size_t)k], pc->arm.tool,
                                                         pinocchio::LOCAL_WORLD_ALIGNED, pc->J);
                                                     sum += pc->J(0, last));
                                          ns.insert(ns.end(), pc->ns_block.begin(), pc->ns_block.end());
                                          return true;
                                      }, {}, {}});
#endif
            group = rows.size() - first;
        }
    }

    // ---- interleaved rounds; the starting library rotates each round so
    // none is always first after another's block ----
    double checksum = 0.0;
    for (int r = 0; r < BENCH_ROUNDS; r++)
        for (size_t g = 0; g < rows.size(); g += group)
            for (size_t i = 0; i < group; i++) {
                Series &s = rows[g + (i + (size_t)r) % group];
                if (!s.block(s.ns, checksum))
                    return 1;
            }
    for (Series &s : rows)
        s.s = bench_summarize(s.ns.data(), (int)s.ns.size());

    std::printf("\nper call, ns; ratio = median / kinctl double median (same model and op): "
                "above 1 means kinctl double is faster\n");
    std::printf("%-10s %-8s %-6s %-4s %9s %9s %9s %7s\n", "library", "model", "prec", "op", "median", "p99", "max",
                "ratio");
    for (const Series &r : rows) {
        const bench_stats *base = find(rows, "kinctl", r.model, "double", r.op);
        std::printf("%-10s %-8s %-6s %-4s %9.1f %9.1f %9.1f %7.2f\n", r.lib.c_str(), r.model.c_str(), r.prec.c_str(),
                    r.op.c_str(), r.s.median_ns, r.s.p99_ns, r.s.max_ns, r.s.median_ns / base->median_ns);
    }
    std::printf("\ntargets (puma560, double, ratio of medians):\n");
    target(rows, "KDL", "fk", 2.0);
    target(rows, "Pinocchio", "fk", 1.0);
    target(rows, "KDL", "jac", 4.0);
    target(rows, "Pinocchio", "jac", 1.5);
    std::printf("checksum %.17g\n", checksum);
    return 0;
}
