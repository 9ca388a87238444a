// OMPL's Dubins state space behind a C ABI, for fieldguide's oracle tests and
// benchmark. Lengths are in metres (OMPL's lengths, normalised by the turning
// radius, times the radius); segment kinds are 0 left, 1 straight, 2 right, as
// OMPL numbers them.
#include <ompl/base/spaces/DubinsStateSpace.h>

namespace ob = ompl::base;

struct FgOmplDubins {
    double radius;
    ob::DubinsStateSpace space;
    ob::State *from;
    ob::State *to;
    explicit FgOmplDubins(double r) : radius(r), space(r), from(space.allocState()), to(space.allocState()) {}
    ~FgOmplDubins() {
        space.freeState(from);
        space.freeState(to);
    }
    FgOmplDubins(const FgOmplDubins &) = delete;
    FgOmplDubins &operator=(const FgOmplDubins &) = delete;
};

extern "C" {

FgOmplDubins *fg_ompl_dubins_new(double radius) {
    try {
        return new FgOmplDubins(radius);
    } catch (...) {
        return nullptr;
    }
}

void fg_ompl_dubins_free(FgOmplDubins *d) { delete d; }

// The shortest path OMPL finds from (x0, y0, h0) to (x1, y1, h1): its three
// segment kinds into `kinds`, their lengths in metres into `lengths`, and its
// total length in metres returned; -1 when OMPL threw.
double fg_ompl_dubins_shortest(FgOmplDubins *d, double x0, double y0, double h0, double x1, double y1,
                               double h1, int kinds[3], double lengths[3]) {
    try {
        auto *a = d->from->as<ob::SE2StateSpace::StateType>();
        a->setXY(x0, y0);
        a->setYaw(h0);
        auto *b = d->to->as<ob::SE2StateSpace::StateType>();
        b->setXY(x1, y1);
        b->setYaw(h1);
        const ob::DubinsStateSpace::DubinsPath path = d->space.dubins(d->from, d->to);
        for (int i = 0; i < 3; ++i) {
            kinds[i] = static_cast<int>(path.type_[i]);
            lengths[i] = path.length_[i] * d->radius;
        }
        return path.length() * d->radius;
    } catch (...) {
        return -1.0;
    }
}
}
