/* SPDX-License-Identifier: BSD-3-Clause */
// interp_jerk_bench.cpp - kinctl's jerk-limited profiles (kinctl/scurve.h)
// beside Ruckig (issue 19): the puma560 (6 joints) and the panda (7 joints)
// with kinctl's model limits (qd_max, qdd_max, qddd_max), BENCH_JERK_CASES
// random moves each (start and goal uniform within the position limits),
// rest to rest and from random moving states (|v0| <= 0.8 vmax,
// |a0| <= 0.8 amax, with the velocity that a0 alone reaches within vmax),
// and joint by joint from starts outside the limits (up to 1.5 times).
//
// Measured, kinctl in double (the core linked in; the float build's
// figures come from unit.scurve.float, not timed here):
//   durations    kc_interp_joint_plan_cfg (jerk, every joint synchronised;
//                from a moving start by time) against Ruckig's
//                Synchronization::Time and ::Phase; from moving starts also
//                every joint's own kc_scurve_plan against Ruckig<1> on that
//                joint alone (the one-dimensional optimum);
//   limits       every tick of every kinctl plan: speed, acceleration, and
//                jerk as the change of acceleration per tick (slack: 1e-9
//                relative plus 64 double ulps of the scale);
//   planning     one call per case, timed alone (CLOCK_MONOTONIC; the
//                clock's cost, about 20 ns, is in both libraries' figures);
//   evaluation   random ticks, BENCH_BATCH on one plan per timed batch:
//                kc_interp_joint_eval (q, qd, qdd, qddd of every joint) and
//                Trajectory::at_time (position, velocity, acceleration).
// Targets (issue 19): no limit exceeded; rest-to-rest durations within
// 0.1 % of Ruckig's phase-synchronised ones plus one tick; planning median
// at most Ruckig's; evaluation median at most 100 ns per joint per tick.
// The last figures measured are in docs/testing.md.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include <ruckig/ruckig.hpp>

#include "kinctl/chain.h"
#include "kinctl/interp.h"
#include "kinctl/scurve.h"

#include "bench_common.h"
#include "bench_models.hpp"

namespace {

constexpr int CASES = 10000;
constexpr double DT = BENCH_INTERP_DT;
constexpr uint64_t SEED = 20261202u;

struct Stats {
    std::vector<double> ns;
    bench_stats s{};
    void done() { s = bench_summarize(ns.data(), (int)ns.size()); }
};

struct Limits {
    int n = 0;
    double V[BENCH_MAX_JOINTS], A[BENCH_MAX_JOINTS], J[BENCH_MAX_JOINTS];
};

struct Case {
    double q0[BENCH_MAX_JOINTS], q1[BENCH_MAX_JOINTS], v0[BENCH_MAX_JOINTS], a0[BENCH_MAX_JOINTS];
    // A start outside the limits: |v| and |a| up to 1.5 times them.
    double v0x[BENCH_MAX_JOINTS], a0x[BENCH_MAX_JOINTS];
    double frac[BENCH_BATCH];
};

// What a start allows (as tests/unit/test_scurve.c): the speed a0 alone
// carries beyond vmax, the start's own speed and acceleration.
double speed_bound(double v0, double a0, double V, double J)
{
    double vn = std::fabs(v0 + a0 * std::fabs(a0) / (2.0 * J));
    return std::max({V, std::fabs(v0), vn});
}

// Checks every tick of one joint's samples; returns the violations.
struct Walk {
    double v_prev = 0.0, a_prev = 0.0;
    long long bad = 0;
    void step(long long k, double v, double a, double V, double A, double J, double T)
    {
        // V and A: the bounds the start allows (speed_bound, max(A, |a0|)).
        // Rounding of t = k dt and of the sums (tests/unit/test_scurve.c).
        double slack = 64.0 * 2.2e-16;
        if (std::fabs(v) > V * (1.0 + 1e-9) + slack * (V + A * T) ||
            std::fabs(a) > A * (1.0 + 1e-9) + slack * (A + J * T) ||
            (k > 0 && std::fabs(a - a_prev) > J * DT * (1.0 + 1e-9) + slack * (A + J * T)))
            bad++;
        v_prev = v;
        a_prev = a;
    }
};

// Walks every tick of a joint move p of duration T within lim; returns the
// violations over all its joints.
template <size_t N> long long walk_move(const kc_interp_joint &p, const Limits &lim, double T)
{
    Walk w[N];
    kc_interp_joint_state s;
    for (long long t = 0; t <= p.ticks; t++) {
        kc_interp_joint_eval(&p, t, &s);
        for (size_t j = 0; j < N; j++)
            w[j].step(t, s.qd[j], s.qdd[j], lim.V[j], lim.A[j], lim.J[j], T);
    }
    long long bad = 0;
    for (size_t j = 0; j < N; j++)
        bad += w[j].bad;
    return bad;
}

// Times kc_interp_joint_eval on a batch of random ticks of p (c.frac);
// returns the time per call, adding the positions to sum so that the calls
// stay.
double time_ticks(const kc_interp_joint &p, const Case &c, double &sum)
{
    kc_interp_joint_state es;
    double t0 = bench_now_ns();
    for (int i = 0; i < BENCH_BATCH; i++) {
        kc_interp_joint_eval(&p, bench_interp_tick(c.frac[i], p.ticks), &es);
        sum += es.q[0];
    }
    double t1 = bench_now_ns();
    return (t1 - t0) / BENCH_BATCH;
}

// Times Trajectory::at_time on the same batch of random instants of a
// Ruckig trajectory of duration T; returns the time per call.
template <size_t N> double time_ruckig_ticks(const ruckig::Trajectory<N> &tr, const Case &c, double T, double &sum)
{
    std::array<double, N> pos, vel, acc;
    double t0 = bench_now_ns();
    for (int i = 0; i < BENCH_BATCH; i++) {
        tr.at_time(c.frac[i] * T, pos, vel, acc);
        sum += pos[0];
    }
    double t1 = bench_now_ns();
    return (t1 - t0) / BENCH_BATCH;
}

struct Row {
    std::string what;
    Stats st;
};

template <size_t N> struct ModelBench {
    const char *name;
    int model;
    Limits lim;
    std::vector<Case> cases;
    std::vector<Row> rows;
    bool ok = true;

    void line(const char *fmt, double a, double b, bool met)
    {
        std::printf(fmt, a, b, met ? "met" : "MISSED");
        ok &= met;
    }

    // The evaluation target: kinctl's median per joint, Ruckig's beside it.
    void tick_line(const Stats &k, const Stats &r)
    {
        bool met = k.s.median_ns / N <= 100.0;
        std::printf("    tick median per joint <= 100 ns: %.1f ns (p99 %.1f; Ruckig %.1f, p99 %.1f)  %s\n",
                    k.s.median_ns / N, k.s.p99_ns / N, r.s.median_ns / N, r.s.p99_ns / N, met ? "met" : "MISSED");
        ok &= met;
    }

    // The planning target (median), with both p99s beside it.
    void plan_line(const char *what, const Stats &k, const Stats &r)
    {
        bool met = k.s.median_ns <= r.s.median_ns;
        std::printf("%s: %.0f vs %.0f ns (p99 %.0f vs %.0f)  %s\n", what, k.s.median_ns, r.s.median_ns, k.s.p99_ns,
                    r.s.p99_ns, met ? "met" : "MISSED");
        ok &= met;
    }

    ruckig::InputParameter<N> input(const Case &c, bool moving, ruckig::Synchronization sync) const
    {
        ruckig::InputParameter<N> in;
        for (size_t j = 0; j < N; j++) {
            in.current_position[j] = c.q0[j];
            in.current_velocity[j] = moving ? c.v0[j] : 0.0;
            in.current_acceleration[j] = moving ? c.a0[j] : 0.0;
            in.target_position[j] = c.q1[j];
            in.target_velocity[j] = 0.0;
            in.target_acceleration[j] = 0.0;
            in.max_velocity[j] = lim.V[j];
            in.max_acceleration[j] = lim.A[j];
            in.max_jerk[j] = lim.J[j];
        }
        in.synchronization = sync;
        return in;
    }

    // Ruckig's input for joint j alone: from q0 moving at v0, a0 to rest at q1.
    ruckig::InputParameter<1> input1(double q0, double v0, double a0, double q1, size_t j) const
    {
        ruckig::InputParameter<1> in;
        in.current_position[0] = q0;
        in.current_velocity[0] = v0;
        in.current_acceleration[0] = a0;
        in.target_position[0] = q1;
        in.max_velocity[0] = lim.V[j];
        in.max_acceleration[0] = lim.A[j];
        in.max_jerk[0] = lim.J[j];
        return in;
    }

    kc_interp_joint_cfg cfg(const Case &c, bool moving = false) const
    {
        kc_interp_joint_cfg g = kc_interp_joint_cfg_default();
        for (size_t j = 0; j < N && moving; j++) {
            g.qd0[j] = c.v0[j];
            g.qdd0[j] = c.a0[j];
        }
        g.n = (int)N;
        g.dt = DT;
        g.profile = KC_PROFILE_JERK;
        for (size_t j = 0; j < N; j++) {
            g.q0[j] = c.q0[j];
            g.q1[j] = c.q1[j];
            g.qd_max[j] = lim.V[j];
            g.qdd_max[j] = lim.A[j];
            g.qddd_max[j] = lim.J[j];
        }
        return g;
    }

    void make_cases()
    {
        uint64_t state = SEED + (uint64_t)model;
        cases.resize(CASES);
        for (Case &c : cases) {
            bench_uniform_q(model, &state, c.q0);
            bench_uniform_q(model, &state, c.q1);
            for (size_t j = 0; j < N; j++) {
                do {
                    c.a0[j] = lim.A[j] * 0.8 * (2.0 * bench_uniform01(&state) - 1.0);
                    c.v0[j] = lim.V[j] * 0.8 * (2.0 * bench_uniform01(&state) - 1.0);
                } while (speed_bound(c.v0[j], c.a0[j], lim.V[j], lim.J[j]) > lim.V[j]);
                c.v0x[j] = lim.V[j] * 1.5 * (2.0 * bench_uniform01(&state) - 1.0);
                c.a0x[j] = lim.A[j] * 1.5 * (2.0 * bench_uniform01(&state) - 1.0);
            }
            for (double &f : c.frac)
                f = bench_uniform01(&state);
        }
    }

    void rest_to_rest()
    {
        ruckig::Ruckig<N> otg{DT};
        ruckig::Trajectory<N> tr;
        std::vector<kc_interp_joint> plans(64);
        std::vector<ruckig::Trajectory<N>> rtr(64);
        Stats kplan, rplan, ktick, rtick;
        double worst_phase = 0.0, worst_time = 0.0, mean_phase = 0.0;
        long long off = 0, bad = 0, phase_sync = 0;
        double sum = 0.0;
        for (int k = 0; k < CASES; k++) {
            const Case &c = cases[(size_t)k];
            kc_interp_joint_cfg g = cfg(c);
            kc_interp_joint &p = plans[(size_t)k % plans.size()];
            double t0 = bench_now_ns();
            kc_status st = kc_interp_joint_plan_cfg(&p, &g);
            double t1 = bench_now_ns();
            kplan.ns.push_back(t1 - t0);
            auto in_t = input(c, false, ruckig::Synchronization::Time);
            auto in_p = input(c, false, ruckig::Synchronization::Phase);
            ruckig::Trajectory<N> &rt = rtr[(size_t)k % rtr.size()];
            t0 = bench_now_ns();
            ruckig::Result rr = otg.calculate(in_t, rt);
            t1 = bench_now_ns();
            rplan.ns.push_back(t1 - t0);
            ruckig::Result rp = otg.calculate(in_p, tr);
            if (st != KC_OK || rr != ruckig::Result::Working || rp != ruckig::Result::Working) {
                std::printf("  error: case %d: kinctl %d, Ruckig %d %d\n", k, (int)st, (int)rr, (int)rp);
                ok = false;
                return;
            }
            double Tk = (double)p.T, Tt = rt.get_duration(), Tp = tr.get_duration();
            phase_sync += p.sync == KC_INTERP_SYNC_PHASE;
            worst_phase = std::max(worst_phase, Tk / Tp - 1.0);
            worst_time = std::max(worst_time, Tk / Tt - 1.0);
            mean_phase += Tk / Tp - 1.0;
            off += std::fabs(Tk - Tp) > 1e-3 * Tp + DT;
            // Every tick within every joint's limits.
            bad += walk_move<N>(p, lim, Tk);
            // Evaluation: a batch of random ticks on this plan, once the
            // ring of plans is full (every plan in it is fresh).
            ktick.ns.push_back(time_ticks(p, c, sum));
            rtick.ns.push_back(time_ruckig_ticks(rt, c, Tt, sum));
        }
        for (Stats *x : {&kplan, &rplan, &ktick, &rtick})
            x->done();
        std::printf("  rest to rest, %d moves (%lld synchronised by phase, the rest by time): duration / Ruckig "
                    "phase-synchronised: worst +%.2e, mean %+.2e; / Ruckig time-synchronised: worst +%.2e\n",
                    CASES, phase_sync, worst_phase, mean_phase / CASES, worst_time);
        line("    limits: %.0f ticks over a limit (of %.0f moves)  %s\n", (double)bad, (double)CASES, bad == 0);
        line("    durations within 0.1 %% + one tick of Ruckig phase-synchronised: %.0f moves outside (of %.0f)  %s\n",
             (double)off, (double)CASES, off == 0);
        rows.push_back({"rest-to-rest plan  kinctl", kplan});
        rows.push_back({"rest-to-rest plan  Ruckig", rplan});
        rows.push_back({"rest-to-rest tick  kinctl", ktick});
        rows.push_back({"rest-to-rest tick  Ruckig", rtick});
        plan_line("    planning median kinctl <= Ruckig", kplan, rplan);
        tick_line(ktick, rtick);
        if (sum == 12345.678)
            std::printf(" ");
    }

    void moving()
    {
        ruckig::Ruckig<N> otg{DT};
        ruckig::Ruckig<1> one{DT};
        ruckig::Trajectory<N> tr;
        ruckig::Trajectory<1> t1d;
        std::vector<kc_scurve> prof(N);
        // Each planner writes its result into the next of a ring of 64, as
        // in rest_to_rest().
        std::vector<kc_interp_joint> plans(64);
        std::vector<ruckig::Trajectory<N>> rtr(64);
        Stats kplan, kplan1, rplan, ktick, rtick;
        std::vector<double> ratio;
        double worst_t = 0.0, worst_p = 0.0, best_t = 1e9, worst_1 = 0.0;
        long long bad = 0, gap = 0, off = 0;
        double sum = 0.0;
        for (int k = 0; k < CASES; k++) {
            const Case &c = cases[(size_t)k];
            // Each joint alone (its optimum), timed as one call for all.
            double t0 = bench_now_ns();
            kc_status st = KC_OK;
            for (size_t j = 0; j < N; j++)
                st = (kc_status)(st | kc_scurve_plan(&prof[j], c.q0[j], c.v0[j], c.a0[j], c.q1[j], lim.V[j], lim.A[j],
                                                     lim.J[j], DT));
            double t1 = bench_now_ns();
            kplan1.ns.push_back(t1 - t0);
            // The synchronised move.
            kc_interp_joint_cfg g = cfg(c, true);
            kc_interp_joint &p = plans[(size_t)k % plans.size()];
            t0 = bench_now_ns();
            kc_status ss = kc_interp_joint_plan_cfg(&p, &g);
            t1 = bench_now_ns();
            kplan.ns.push_back(t1 - t0);
            auto in_t = input(c, true, ruckig::Synchronization::Time);
            ruckig::Trajectory<N> &rt = rtr[(size_t)k % rtr.size()];
            t0 = bench_now_ns();
            ruckig::Result rr = otg.calculate(in_t, rt);
            t1 = bench_now_ns();
            rplan.ns.push_back(t1 - t0);
            if (st != KC_OK || ss != KC_OK || rr != ruckig::Result::Working) {
                std::printf("  error: moving case %d: kinctl %d %d, Ruckig %d\n", k, (int)st, (int)ss, (int)rr);
                ok = false;
                return;
            }
            double Tt = rt.get_duration();
            rtick.ns.push_back(time_ruckig_ticks(rt, c, Tt, sum));
            auto in_p = input(c, true, ruckig::Synchronization::Phase);
            otg.calculate(in_p, tr);
            double Tp = tr.get_duration(), Tk = (double)p.T, T1 = 0.0;
            for (size_t j = 0; j < N; j++) {
                T1 = std::max(T1, (double)prof[j].T);
                gap += prof[j].gap;
                auto in1 = input1(c.q0[j], c.v0[j], c.a0[j], c.q1[j], j);
                if (one.calculate(in1, t1d) == ruckig::Result::Working)
                    ratio.push_back((double)prof[j].T / t1d.get_duration());
            }
            bad += walk_move<N>(p, lim, Tk);
            worst_t = std::max(worst_t, Tk / Tt - 1.0);
            best_t = std::min(best_t, Tk / Tt - 1.0);
            worst_p = std::max(worst_p, Tk / Tp - 1.0);
            worst_1 = std::max(worst_1, Tk / T1 - 1.0);
            off += std::fabs(Tk - Tt) > 1e-3 * Tt + DT;
            ktick.ns.push_back(time_ticks(p, c, sum));
        }
        for (Stats *x : {&kplan, &kplan1, &rplan, &ktick, &rtick})
            x->done();
        std::sort(ratio.begin(), ratio.end());
        size_t n = ratio.size(), above = (size_t)std::count_if(ratio.begin(), ratio.end(),
                                                                  [](double r) { return r > 1.0 + 1e-6; });
        std::printf("  moving starts, %d moves, %zu joints: joint duration / Ruckig<1>'s optimum: median %.6f, "
                    "p99 %.6f, max %.4f, %zu joints (%.2f %%) longer by more than 1e-6, %lld planned by the gap "
                    "family\n",
                    CASES, n, ratio[n / 2], ratio[(99 * n) / 100], ratio[n - 1], above, 100.0 * (double)above / (double)n,
                    gap);
        std::printf("    synchronised (time) duration / Ruckig time-synchronised: %+.2e..%+.2e, %lld moves off by "
                    "more than 0.1 %% + one tick; / Ruckig phase-synchronised: worst %+.2e; / the slowest joint's "
                    "optimum: worst %+.2e\n",
                    best_t, worst_t, off, worst_p, worst_1);
        line("    limits: %.0f ticks over a limit (of %.0f moves)  %s\n", (double)bad, (double)CASES, bad == 0);
        rows.push_back({"moving plan        kinctl", kplan});
        rows.push_back({"moving plan 1-D x N kinctl", kplan1});
        rows.push_back({"moving plan        Ruckig", rplan});
        rows.push_back({"moving tick        kinctl", ktick});
        rows.push_back({"moving tick        Ruckig", rtick});
        plan_line("    planning median kinctl <= Ruckig (synchronised)", kplan, rplan);
        tick_line(ktick, rtick);
        if (sum == 12345.678)
            std::printf(" ");
    }

    // Starts outside the limits, joint by joint against Ruckig<1>: the
    // duration ratio (the bound kinctl/scurve.h states for such starts is
    // measured here) and every tick within what the start allows.
    void outside()
    {
        ruckig::Ruckig<1> one{DT};
        ruckig::Trajectory<1> t1d;
        kc_scurve prof;
        std::vector<double> ratio;
        long long bad = 0, failed = 0, gap = 0;
        for (int k = 0; k < CASES; k++) {
            const Case &c = cases[(size_t)k];
            for (size_t j = 0; j < N; j++) {
                if (kc_scurve_plan(&prof, c.q0[j], c.v0x[j], c.a0x[j], c.q1[j], lim.V[j], lim.A[j], lim.J[j], DT) !=
                    KC_OK) {
                    failed++;
                    continue;
                }
                gap += prof.gap;
                auto in1 = input1(c.q0[j], c.v0x[j], c.a0x[j], c.q1[j], j);
                if (one.calculate(in1, t1d) == ruckig::Result::Working)
                    ratio.push_back((double)prof.T / t1d.get_duration());
                Walk w;
                kc_scurve_state s;
                double vb = speed_bound(c.v0x[j], c.a0x[j], lim.V[j], lim.J[j]);
                double ab = std::max(lim.A[j], std::fabs(c.a0x[j]));
                for (long long t = 0; t <= prof.ticks; t++) {
                    kc_scurve_eval(&prof, t, &s);
                    w.step(t, s.v, s.a, vb, ab, lim.J[j], (double)prof.T);
                }
                bad += w.bad;
            }
        }
        std::sort(ratio.begin(), ratio.end());
        if (ratio.empty()) {
            std::printf("  starts outside the limits: Ruckig<1> planned none of them\n");
            ok = false;
            return;
        }
        size_t n = ratio.size(), above = (size_t)std::count_if(ratio.begin(), ratio.end(),
                                                                  [](double r) { return r > 1.0 + 1e-6; });
        std::printf("  starts outside the limits (|v0| <= 1.5 vmax, |a0| <= 1.5 amax), %zu joints against Ruckig<1>: "
                    "duration ratio median %.6f, p99 %.6f, max %.4f, min %.4f; %zu (%.2f %%) longer by more than "
                    "1e-6; %lld planned by the gap family\n",
                    n, ratio[n / 2], ratio[(99 * n) / 100], ratio[n - 1], ratio[0], above,
                    100.0 * (double)above / (double)n, gap);
        line("    limits (speed: max(vmax, |v0|, |vn|); acceleration: max(amax, |a0|)): %.0f ticks over (%.0f plans "
             "failed)  %s\n",
             (double)bad, (double)failed, bad == 0 && failed == 0);
    }

    bool run()
    {
        kc_chain chain;
        if (kc_chain_init_model(&chain, model == BENCH_PUMA560 ? KC_MODEL_PUMA560 : KC_MODEL_PANDA, nullptr) != KC_OK ||
            chain.n_joints != (int)N)
            return false;
        lim.n = (int)N;
        for (size_t j = 0; j < N; j++) {
            lim.V[j] = chain.joints[j].limits.qd_max;
            lim.A[j] = chain.joints[j].limits.qdd_max;
            lim.J[j] = chain.joints[j].limits.qddd_max;
        }
        std::printf("\n%s (%zu joints), kinctl's model limits: qd_max", name, N);
        for (size_t j = 0; j < N; j++)
            std::printf(" %g", lim.V[j]);
        std::printf(", qdd_max");
        for (size_t j = 0; j < N; j++)
            std::printf(" %g", lim.A[j]);
        std::printf(", qddd_max");
        for (size_t j = 0; j < N; j++)
            std::printf(" %g", lim.J[j]);
        std::printf("\n");
        make_cases();
        rest_to_rest();
        moving();
        outside();
        std::printf("  %-26s %9s %9s %9s\n", "ns per call", "median", "p99", "max");
        for (const Row &r : rows)
            std::printf("  %-26s %9.1f %9.1f %9.1f\n", r.what.c_str(), r.st.s.median_ns, r.st.s.p99_ns, r.st.s.max_ns);
        return ok;
    }
};

} // namespace

int main()
{
    std::printf("interp_jerk_bench: %d random moves per model, dt %g s, kinctl %s, %s\n", CASES, DT, KC_REAL_NAME,
                kcb::pin_to_one_cpu().c_str());
    ModelBench<6> puma{"puma560", BENCH_PUMA560, {}, {}, {}};
    ModelBench<7> panda{"panda", BENCH_PANDA, {}, {}, {}};
    bool ok = puma.run();
    ok = panda.run() && ok;
    std::printf("\nall targets %s\n", ok ? "met" : "NOT met");
    return ok ? 0 : 1;
}
