/* SPDX-License-Identifier: BSD-3-Clause */
// interp_bench.cpp - planning cost and per-tick cost of kinctl's motion
// planners (joint move, line, arc, multi-point paths in joint and Cartesian
// space), beside Orocos KDL's VelocityProfile_Trap and Ruckig on the same
// 6-joint synchronised moves (issue 4).
//
// kinctl runs in its helpers (interp_helper.c, one per precision), KDL and
// Ruckig here, all pinned to one CPU. Every series is timed in BENCH_ROUNDS
// blocks interleaved with the other series of its motion and op (the
// machine's speed drifts). Plan series call the planner on a different
// input every call; tick series evaluate random ticks over the whole motion
// (bench_common.h).
//
// The compared operations, for the puma560 move set of bench_common.h with
// kinctl's own puma560 rate limits:
//   kinctl plan  kc_interp_joint_plan (fastest synchronised move);
//   kinctl tick  kc_interp_joint_eval (q, qd, qdd of 6 joints at tick k);
//   KDL plan     six VelocityProfile_Trap::SetProfile, the longest Duration,
//                then SetProfileDuration of all six to it;
//   KDL tick     Pos, Vel and Acc of all six at t = k dt;
//   Ruckig plan  Ruckig<6>::calculate of the rest-to-rest move with the
//                same velocity and acceleration limits and kinctl's jerk
//                limits (10 x the acceleration limit per second): jerk-
//                limited, so a harder problem than a trapezoid;
//   Ruckig tick  Trajectory<6>::at_time at t = k dt (the evaluation alone);
//   Ruckig update Ruckig<6>::update on consecutive cycles of whole moves
//                without recalculation (its online interface per cycle).
//
// Before timing, kinctl's joint moves are checked against KDL's stretched
// profiles: same duration and same positions of the leading joint. The
// other joints are compared too but not judged: KDL stretches a profile by
// scaling time (SetProfileDuration multiplies velocities by T0/T and
// accelerations by (T0/T)^2), kinctl keeps the acceleration and lowers the
// cruise speed (kinctl/profile.h), so only the unstretched leading joint has
// the same positions in both.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <kdl/velocityprofile_trap.hpp>

#ifdef KC_BENCH_WITH_RUCKIG
#include <ruckig/ruckig.hpp>
#endif

#include "bench_common.h"
#include "bench_models.hpp"

// The double build of the core, for its tick count alone: the timed kinctl
// calls run in the helpers (one per precision).
#include "kinctl/profile.h"

namespace {

using namespace kcb;

constexpr int N = 6;
constexpr double DT = BENCH_INTERP_DT;

// Issue 4's targets (ns, medians).
constexpr double TARGET_SEGMENT_TICK_NS = 150.0;
constexpr double TARGET_PATH_TICK_NS = 200.0;

// ---- what a helper's `check` says ----

struct MotionInfo {
    std::string name;
    int ok = 0, total = 0;
    long long ticks_min = 0, ticks_median = 0, ticks_max = 0;
};

struct JointCheck {
    double T = 0.0;
    long long ticks = 0;
    int lead = -1;
    std::vector<std::pair<long long, std::vector<double>>> pos; // (tick, q)
};

struct HelperCheck {
    std::vector<double> qd, qdd, qddd;
    std::vector<MotionInfo> motions;
    std::vector<JointCheck> joints;
    std::vector<std::string> failures;
};

bool helper_check(const char *path, HelperCheck &hc)
{
    std::string out;
    if (!run_helper(path, "check", out))
        return false;
    hc.joints.assign(BENCH_CHECKS, JointCheck{});
    size_t pos = 0;
    for (size_t eol; (eol = out.find('\n', pos)) != std::string::npos; pos = eol + 1) {
        std::string line = out.substr(pos, eol - pos);
        char word[16], name[64];
        int a = 0, b = 0, used = 0;
        long long t0 = 0, t1 = 0, t2 = 0;
        double T = 0.0;
        bool ok = std::sscanf(line.c_str(), "%15s", word) == 1;
        if (ok && std::strcmp(word, "limits") == 0) {
            std::vector<double> v = parse_numbers(line.c_str() + 6);
            ok = v.size() == 3 * N;
            if (ok) {
                hc.qd.assign(v.begin(), v.begin() + N);
                hc.qdd.assign(v.begin() + N, v.begin() + 2 * N);
                hc.qddd.assign(v.begin() + 2 * N, v.end());
            }
        } else if (ok && std::strcmp(word, "motion") == 0) {
            ok = std::sscanf(line.c_str(), "motion %63s %d %d %lld %lld %lld", name, &a, &b, &t0, &t1, &t2) == 6;
            if (ok)
                hc.motions.push_back(MotionInfo{name, a, b, t0, t1, t2});
        } else if (ok && std::strcmp(word, "status") == 0) {
            hc.failures.push_back(line);
        } else if (ok && std::strcmp(word, "joint") == 0) {
            ok = std::sscanf(line.c_str(), "joint %d %lf %lld %d", &a, &T, &t0, &b) == 4 && a >= 0 &&
                 a < BENCH_CHECKS;
            if (ok) {
                hc.joints[(size_t)a].T = T;
                hc.joints[(size_t)a].ticks = t0;
                hc.joints[(size_t)a].lead = b;
            }
        } else if (ok && std::strcmp(word, "pos") == 0) {
            ok = std::sscanf(line.c_str(), "pos %d %lld %n", &a, &t0, &used) == 2 && used > 0 && a >= 0 &&
                 a < BENCH_CHECKS;
            std::vector<double> q = ok ? parse_numbers(line.c_str() + used) : std::vector<double>();
            ok = ok && q.size() == N;
            if (ok)
                hc.joints[(size_t)a].pos.emplace_back(t0, q);
        } else {
            ok = false;
        }
        if (!ok) {
            std::printf("error: %s check: %s\n", path, line.c_str());
            return false;
        }
    }
    if (hc.qd.size() != N || hc.motions.empty()) {
        std::printf("error: %s check gave no limits or no motions\n", path);
        return false;
    }
    return true;
}

// ---- KDL ----

using KdlMove = std::array<KDL::VelocityProfile_Trap, N>;

// The synchronised move as a KDL user plans it: each joint's fastest
// trapezoid, then all stretched to the longest. Returns the duration.
inline double kdl_plan(KdlMove &m, const double *q0, const double *q1)
{
    double T = 0.0;
    for (int j = 0; j < N; j++) {
        m[(size_t)j].SetProfile(q0[j], q1[j]);
        T = std::max(T, m[(size_t)j].Duration());
    }
    for (int j = 0; j < N; j++)
        m[(size_t)j].SetProfileDuration(q0[j], q1[j], T);
    return T;
}

// First tick k with k dt >= T, counted by the core itself (kinctl/profile.h:
// kc_profile.ticks): the ticks of a rest-to-rest profile of no distance that
// lasts exactly T. -1 when the core cannot count them (T over its capacity).
inline long long ticks_of(double T)
{
    kc_profile hold;
    if (kc_profile_plan_duration(&hold, 0.0, 0.0, 1.0, 1.0, T, DT) != KC_OK)
        return -1;
    return (long long)hold.ticks;
}

// The move set and, per tick sample, its plan and time.
struct MoveSet {
    double q0[BENCH_CONFIGS][BENCH_MAX_JOINTS], q1[BENCH_CONFIGS][BENCH_MAX_JOINTS], frac[BENCH_CONFIGS];
};

struct KdlCtx {
    KdlMove plan;                    // the plan series' output
    std::vector<KdlMove> tick_plans; // BENCH_INTERP_TICK_PLANS
    std::array<double, N> pos, vel, acc;
    std::vector<double> t_of = std::vector<double>(BENCH_CONFIGS);
    std::vector<double> ns_block = std::vector<double>(BENCH_BATCHES_PER_ROUND);
};

#ifdef KC_BENCH_WITH_RUCKIG
using RInput = ruckig::InputParameter<N>;
using ROutput = ruckig::OutputParameter<N>;
using RTraj = ruckig::Trajectory<N>;

struct RuckigCtx {
    ruckig::Ruckig<N> otg{DT};
    RInput input; // limits set once; positions per move
    RTraj traj;   // the plan series' output
    std::vector<RTraj> tick_plans;
    std::array<double, N> pos, vel, acc;
    std::vector<double> t_of = std::vector<double>(BENCH_CONFIGS);
    std::vector<double> ns_block = std::vector<double>(BENCH_BATCHES_PER_ROUND);
    // update(): the running move
    ruckig::Ruckig<N> online{DT};
    RInput uin;
    ROutput uout;
    int umove = 0;
};

inline void ruckig_set_move(RInput &in, const double *q0, const double *q1)
{
    for (int j = 0; j < N; j++) {
        in.current_position[(size_t)j] = q0[j];
        in.target_position[(size_t)j] = q1[j];
    }
}

// Starts move m on the online generator: its first update computes the
// trajectory, outside any timed batch.
bool ruckig_start(RuckigCtx &rc, const MoveSet &ms, int m)
{
    rc.umove = m;
    rc.uin = rc.input;
    ruckig_set_move(rc.uin, ms.q0[m], ms.q1[m]);
    rc.online.reset();
    ruckig::Result r = rc.online.update(rc.uin, rc.uout);
    rc.uout.pass_to_input(rc.uin);
    if (r != ruckig::Result::Working) {
        std::printf("error: Ruckig update on move %d: result %d\n", m, (int)r);
        return false;
    }
    return true;
}

// BENCH_TIME's schedule for update(): batches of BENCH_BATCH consecutive
// cycles; a move that finishes inside a batch is replaced after it, so a
// recalculation never falls into a timed batch (the cycles after Finished
// evaluate the end state).
bool ruckig_update_block(RuckigCtx &rc, const MoveSet &ms, std::vector<double> &ns, double &sum)
{
    for (int b = -BENCH_WARMUP; b < BENCH_BATCHES_PER_ROUND; b++) {
        bool finished = false;
        double t0 = bench_now_ns();
        for (int i = 0; i < BENCH_BATCH; i++) {
            ruckig::Result r = rc.online.update(rc.uin, rc.uout);
            rc.uout.pass_to_input(rc.uin);
            sum += rc.uout.new_position[0];
            finished |= r == ruckig::Result::Finished;
        }
        double t1 = bench_now_ns();
        if (b >= 0)
            rc.ns_block[(size_t)b] = (t1 - t0) / (double)BENCH_BATCH;
        if (finished && !ruckig_start(rc, ms, (rc.umove + 1) % BENCH_CONFIGS))
            return false;
    }
    ns.insert(ns.end(), rc.ns_block.begin(), rc.ns_block.end());
    return true;
}
#endif

// ---- the check ----

// kinctl (one precision) against KDL on the first BENCH_CHECKS moves:
// duration and leading joint judged, the other joints reported.
bool check_joint(const char *prec, const HelperCheck &hc, const MoveSet &ms, KdlCtx &kc, double tol_T,
                 double tol_q)
{
    double dT = 0.0, dlead = 0.0, dother = 0.0;
    for (int k = 0; k < BENCH_CHECKS; k++) {
        const JointCheck &jc = hc.joints[(size_t)k];
        double T = kdl_plan(kc.plan, ms.q0[k], ms.q1[k]);
        dT = std::max(dT, std::fabs(T - jc.T));
        if (jc.lead < 0 || jc.pos.size() != BENCH_INTERP_CHECK_POINTS)
            return false;
        for (const auto &tp : jc.pos) {
            double t = (double)tp.first * DT;
            for (int j = 0; j < N; j++) {
                double d = std::fabs(kc.plan[(size_t)j].Pos(t) - tp.second[(size_t)j]);
                (j == jc.lead ? dlead : dother) = std::max(j == jc.lead ? dlead : dother, d);
            }
        }
    }
    bool ok = dT <= tol_T && dlead <= tol_q;
    std::printf("  kinctl %-6s vs KDL: duration %8.1e s, leading joint %8.1e rad: %s (tol %.0e s, %.0e rad); "
                "other joints differ by up to %.3f rad (different stretch, not judged)\n",
                prec, dT, dlead, ok ? "ok" : "MISMATCH", tol_T, tol_q, dother);
    return ok;
}

// ---- timing ----

struct Series {
    std::string lib, motion, prec, op;
    std::function<bool(std::vector<double> &ns, double &checksum)> block;
    std::vector<double> ns;
    bench_stats s;
};

const bench_stats *find(const std::vector<Series> &rows, const std::string &lib, const std::string &motion,
                        const std::string &prec, const std::string &op)
{
    for (const Series &r : rows)
        if (r.lib == lib && r.motion == motion && r.prec == prec && r.op == op && !r.ns.empty())
            return &r.s;
    return nullptr;
}

void target_vs(const std::vector<Series> &rows, const char *prec, const char *op, const char *lib)
{
    const bench_stats *k = find(rows, "kinctl", "joint", prec, op), *o = find(rows, lib, "joint", "double", op);
    if (k == nullptr || o == nullptr) {
        std::printf("  joint %-4s kinctl %-6s <= %s: not measured\n", op, prec, lib);
        return;
    }
    std::printf("  joint %-4s kinctl %-6s <= %s: %7.1f vs %7.1f ns  %s\n", op, prec, lib, k->median_ns, o->median_ns,
                k->median_ns <= o->median_ns ? "met" : "MISSED");
}

void target_below(const std::vector<Series> &rows, const std::string &motion, const char *prec, double limit)
{
    const bench_stats *k = find(rows, "kinctl", motion, prec, "tick");
    if (k == nullptr) {
        std::printf("  %-21s tick %-6s < %3.0f ns: not measured\n", motion.c_str(), prec, limit);
        return;
    }
    std::printf("  %-21s tick %-6s < %3.0f ns: %7.1f ns (p99 %7.1f)  %s\n", motion.c_str(), prec, limit, k->median_ns,
                k->p99_ns, k->median_ns < limit ? "met" : "MISSED");
}

} // namespace

int main()
{
    std::printf("interp_bench: puma560 moves, dt %g s; tick series: %d plans x %d random ticks in [0, ticks]; "
                "plan series: a new input every call; per series %d rounds x %d batches (plans %d) of %d calls "
                "(+%d warm-up batches a round), CLOCK_MONOTONIC\n",
                DT, BENCH_INTERP_TICK_PLANS, BENCH_INTERP_TICKS_PER_PLAN, BENCH_ROUNDS, BENCH_BATCHES_PER_ROUND,
                BENCH_INTERP_PLAN_BATCHES, BENCH_BATCH, BENCH_WARMUP);
    std::printf("%s\n", pin_to_one_cpu().c_str());
#ifndef KC_BENCH_WITH_RUCKIG
    std::printf("Ruckig: not built: %s\n", KC_BENCH_RUCKIG_MISSING);
#endif

    HelperCheck dbl, flt;
    if (!helper_check(KC_BENCH_HELPER_DOUBLE, dbl) || !helper_check(KC_BENCH_HELPER_FLOAT, flt))
        return 1;
    std::printf("limits (kinctl's puma560): qd_max");
    for (double v : dbl.qd)
        std::printf(" %g", v);
    std::printf(" rad/s, qdd_max");
    for (double v : dbl.qdd)
        std::printf(" %g", v);
    std::printf(" rad/s^2, jerk (Ruckig)");
    for (double v : dbl.qddd)
        std::printf(" %g", v);
    std::printf(" rad/s^3\n");

    // Every input of every motion must plan: a benchmark of failing
    // planners times error paths.
    bool all_ok = true;
    std::printf("inputs that plan, and their duration in ticks (min / median / max), double | float:\n");
    for (size_t i = 0; i < dbl.motions.size(); i++) {
        const MotionInfo &d = dbl.motions[i];
        const MotionInfo *f = i < flt.motions.size() ? &flt.motions[i] : nullptr;
        std::printf("  %-21s %4d/%d %6lld %6lld %6lld | %4d/%d %6lld %6lld %6lld\n", d.name.c_str(), d.ok, d.total,
                    d.ticks_min, d.ticks_median, d.ticks_max, f ? f->ok : 0, f ? f->total : 0, f ? f->ticks_min : 0,
                    f ? f->ticks_median : 0, f ? f->ticks_max : 0);
        all_ok &= d.ok == d.total && f != nullptr && f->ok == f->total && f->name == d.name;
    }
    for (const std::string &s : dbl.failures)
        std::printf("  double: %s\n", s.c_str());
    for (const std::string &s : flt.failures)
        std::printf("  float: %s\n", s.c_str());

    // ---- KDL and Ruckig on the same moves ----
    static MoveSet ms;
    bench_make_moves(ms.q0, ms.q1, ms.frac);
    auto kc = std::make_unique<KdlCtx>();
    for (int j = 0; j < N; j++)
        kc->plan[(size_t)j].SetMax(dbl.qd[(size_t)j], dbl.qdd[(size_t)j]);
    kc->tick_plans.assign(BENCH_INTERP_TICK_PLANS, kc->plan);
    for (int p = 0; p < BENCH_INTERP_TICK_PLANS; p++) {
        double T = kdl_plan(kc->tick_plans[(size_t)p], ms.q0[p], ms.q1[p]);
        for (int i = 0; i < BENCH_INTERP_TICKS_PER_PLAN; i++) {
            int k = p * BENCH_INTERP_TICKS_PER_PLAN + i;
            kc->t_of[(size_t)k] = (double)bench_interp_tick(ms.frac[k], ticks_of(T)) * DT;
        }
    }

    std::printf("check: joint moves %d..%d, kinctl against KDL's stretched VelocityProfile_Trap; positions at "
                "%d ticks from 0 to the end:\n",
                0, BENCH_CHECKS - 1, BENCH_INTERP_CHECK_POINTS);
    // Float: q rounded to float (6e-8 rad relative) and float arithmetic
    // over moves of a few rad and a few s.
    all_ok &= check_joint("double", dbl, ms, *kc, 1e-9, 1e-9);
    all_ok &= check_joint("float", flt, ms, *kc, 1e-5, 1e-5);

#ifdef KC_BENCH_WITH_RUCKIG
    auto rc = std::make_unique<RuckigCtx>();
    for (int j = 0; j < N; j++) {
        rc->input.max_velocity[(size_t)j] = dbl.qd[(size_t)j];
        rc->input.max_acceleration[(size_t)j] = dbl.qdd[(size_t)j];
        rc->input.max_jerk[(size_t)j] = dbl.qddd[(size_t)j];
    }
    rc->tick_plans.resize(BENCH_INTERP_TICK_PLANS);
    {
        // Ruckig's jerk-limited moves take longer than the trapezoids, and
        // must end on the goal.
        double rmin = INFINITY, rmax = 0.0, dend = 0.0;
        for (int k = 0; k < BENCH_CONFIGS && all_ok; k++) {
            RInput in = rc->input;
            ruckig_set_move(in, ms.q0[k], ms.q1[k]);
            RTraj &tr = k < BENCH_INTERP_TICK_PLANS ? rc->tick_plans[(size_t)k] : rc->traj;
            ruckig::Result r = rc->otg.calculate(in, tr);
            if (r != ruckig::Result::Working) {
                std::printf("error: Ruckig calculate on move %d: result %d\n", k, (int)r);
                all_ok = false;
                break;
            }
            double T = kdl_plan(kc->plan, ms.q0[k], ms.q1[k]);
            rmin = std::min(rmin, tr.get_duration() / T);
            rmax = std::max(rmax, tr.get_duration() / T);
            std::array<double, N> p;
            tr.at_time(tr.get_duration(), p);
            for (int j = 0; j < N; j++)
                dend = std::max(dend, std::fabs(p[(size_t)j] - ms.q1[k][j]));
            if (k < BENCH_INTERP_TICK_PLANS)
                for (int i = 0; i < BENCH_INTERP_TICKS_PER_PLAN; i++) {
                    int s = k * BENCH_INTERP_TICKS_PER_PLAN + i;
                    rc->t_of[(size_t)s] = (double)bench_interp_tick(ms.frac[s], ticks_of(tr.get_duration())) * DT;
                }
        }
        bool ok = all_ok && rmin >= 1.0 - 1e-9 && dend <= 1e-9;
        std::printf("  Ruckig: %d moves, jerk-limited duration / trapezoid duration %.3f..%.3f, end position "
                    "%8.1e rad from the goal: %s\n",
                    BENCH_CONFIGS, rmin, rmax, dend, ok ? "ok" : "MISMATCH");
        all_ok &= ok;
    }
    all_ok = all_ok && ruckig_start(*rc, ms, 0);
#endif
    if (!all_ok) {
        std::printf("a check failed: nothing timed\n");
        return 1;
    }

    // ---- the series, grouped by motion and op; a group's series are
    // interleaved with each other ----
    std::vector<Series> rows;
    std::vector<std::pair<size_t, size_t>> groups; // rows [first, end)
    KdlCtx *kp = kc.get();
#ifdef KC_BENCH_WITH_RUCKIG
    RuckigCtx *rp = rc.get();
#endif
    constexpr int PER = BENCH_INTERP_TICKS_PER_PLAN;
    for (const MotionInfo &mi : dbl.motions) {
        const std::string motion = mi.name;
        for (const std::string op : {"plan", "tick"}) {
            size_t first = rows.size();
            int batches = op == "plan" ? BENCH_INTERP_PLAN_BATCHES : BENCH_BATCHES_PER_ROUND;
            for (const char *prec : {"double", "float"}) {
                const char *path = std::strcmp(prec, "double") == 0 ? KC_BENCH_HELPER_DOUBLE : KC_BENCH_HELPER_FLOAT;
                rows.push_back(Series{"kinctl", motion, prec, op, [=](std::vector<double> &ns, double &sum) {
                                          return helper_block(path, motion + " " + op, batches, ns, sum);
                                      }, {}, {}});
            }
            // The checksum reads one output of every call; every other
            // output goes to memory that outlives the loop, so no
            // computation can be dropped as dead code.
            if (motion == "joint" && op == "plan") {
                rows.push_back(Series{"KDL", motion, "double", op, [=](std::vector<double> &ns, double &sum) {
                                          BENCH_TIME(kp->ns_block, BENCH_INTERP_PLAN_BATCHES,
                                                     sum += kdl_plan(kp->plan, ms.q0[k], ms.q1[k]));
                                          ns.insert(ns.end(), kp->ns_block.begin(),
                                                    kp->ns_block.begin() + BENCH_INTERP_PLAN_BATCHES);
                                          return true;
                                      }, {}, {}});
#ifdef KC_BENCH_WITH_RUCKIG
                rows.push_back(Series{"Ruckig", motion, "double", op, [=](std::vector<double> &ns, double &sum) {
                                          BENCH_TIME(rp->ns_block, BENCH_INTERP_PLAN_BATCHES,
                                                     ruckig_set_move(rp->input, ms.q0[k], ms.q1[k]);
                                                     rp->otg.calculate(rp->input, rp->traj);
                                                     sum += rp->traj.get_duration());
                                          ns.insert(ns.end(), rp->ns_block.begin(),
                                                    rp->ns_block.begin() + BENCH_INTERP_PLAN_BATCHES);
                                          return true;
                                      }, {}, {}});
#endif
            }
            if (motion == "joint" && op == "tick") {
                rows.push_back(Series{"KDL", motion, "double", op, [=](std::vector<double> &ns, double &sum) {
                                          BENCH_TIME(kp->ns_block, BENCH_BATCHES_PER_ROUND, {
                                              const KdlMove &m = kp->tick_plans[(size_t)(k / PER)];
                                              double t = kp->t_of[(size_t)k];
                                              for (size_t j = 0; j < N; j++) {
                                                  kp->pos[j] = m[j].Pos(t);
                                                  kp->vel[j] = m[j].Vel(t);
                                                  kp->acc[j] = m[j].Acc(t);
                                              }
                                              sum += kp->pos[0];
                                          });
                                          ns.insert(ns.end(), kp->ns_block.begin(), kp->ns_block.end());
                                          return true;
                                      }, {}, {}});
#ifdef KC_BENCH_WITH_RUCKIG
                rows.push_back(Series{"Ruckig", motion, "double", op, [=](std::vector<double> &ns, double &sum) {
                                          BENCH_TIME(rp->ns_block, BENCH_BATCHES_PER_ROUND,
                                                     rp->tick_plans[(size_t)(k / PER)].at_time(
                                                         rp->t_of[(size_t)k], rp->pos, rp->vel, rp->acc);
                                                     sum += rp->pos[0]);
                                          ns.insert(ns.end(), rp->ns_block.begin(), rp->ns_block.end());
                                          return true;
                                      }, {}, {}});
                rows.push_back(Series{"Ruckig", motion, "double", "update",
                                      [=](std::vector<double> &ns, double &sum) {
                                          return ruckig_update_block(*rp, ms, ns, sum);
                                      }, {}, {}});
#endif
            }
            groups.emplace_back(first, rows.size());
        }
    }

    // ---- interleaved rounds; the first series of a group rotates each
    // round so none always runs right after another's block ----
    double checksum = 0.0;
    for (int r = 0; r < BENCH_ROUNDS; r++) {
        for (const auto &g : groups) {
            size_t size = g.second - g.first;
            for (size_t i = 0; i < size; i++) {
                Series &s = rows[g.first + (i + (size_t)r) % size];
                if (!s.block(s.ns, checksum))
                    return 1;
            }
        }
        std::fprintf(stderr, "interp_bench: round %d of %d done\n", r + 1, BENCH_ROUNDS);
    }
    for (Series &s : rows)
        s.s = bench_summarize(s.ns.data(), (int)s.ns.size());

    std::printf("\nper call, ns (p99 and max of the means of %d-call batches); ratio = median / kinctl double "
                "median of the same motion and op (Ruckig update: of the tick)\n",
                BENCH_BATCH);
    std::printf("%-8s %-21s %-6s %-6s %9s %9s %9s %7s\n", "library", "motion", "prec", "op", "median", "p99", "max",
                "ratio");
    for (const Series &r : rows) {
        const bench_stats *base = find(rows, "kinctl", r.motion, "double", r.op == "update" ? "tick" : r.op);
        std::printf("%-8s %-21s %-6s %-6s %9.1f %9.1f %9.1f %7.2f\n", r.lib.c_str(), r.motion.c_str(), r.prec.c_str(),
                    r.op.c_str(), r.s.median_ns, r.s.p99_ns, r.s.max_ns, r.s.median_ns / base->median_ns);
    }

    std::printf("\ntargets (issue 4, medians):\n");
    for (const char *prec : {"double", "float"}) {
        target_vs(rows, prec, "plan", "KDL");
        target_vs(rows, prec, "tick", "KDL");
    }
    for (const char *prec : {"double", "float"})
        for (const MotionInfo &mi : dbl.motions) {
            if (mi.name == "joint")
                continue;
            bool path = mi.name.compare(0, 5, "jpath") == 0 || mi.name.compare(0, 5, "cpath") == 0;
            target_below(rows, mi.name, prec, path ? TARGET_PATH_TICK_NS : TARGET_SEGMENT_TICK_NS);
        }
    std::printf("references quoted in the issue: KDL about 150 ns plan and 30 ns tick, Ruckig about 3.5 us "
                "calculate\n");
    std::printf("checksum %.17g\n", checksum);
    return 0;
}
