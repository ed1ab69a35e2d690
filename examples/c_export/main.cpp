// A contact at every touchdown of a bouncing ball: the exact damping for a measured restitution,
// from the C tables that `contactalpha export-c` writes (see CMakeLists.txt).
//
// The scene is the paper's ball (m = 0.5 kg, k = 1.4e8 N/m^1.5) pressed by gravity and a 5.1 N
// force; Newton's restitution e_N = 0.5 was measured.  The damping mu = alpha k / v- belongs to
// one approach speed, so it is computed again for each touchdown speed.
#include <cstdio>

#include "contactalpha.h"

int main() {
    const double mass = 0.5, stiffness = 1.4e8, accel = 9.81 + 5.1 / 0.5, e_n = 0.5;
    const double speeds[] = {0.5, 0.25, 0.1};  // m/s, approach speeds of successive touchdowns
    int failures = 0;
    std::printf("v_minus xi alpha damping\n");
    for (double v : speeds) {
        double xi = 0.0, alpha = 0.0, damping = 0.0;
        int status = contactalpha_contact_parameters(CONTACTALPHA_KINEMATIC, e_n, mass, stiffness, v,
                                                     accel, &xi, &alpha, &damping);
        if (status != CONTACTALPHA_OK) {
            std::fprintf(stderr, "v_minus %g: status %d\n", v, status);
            ++failures;
            continue;
        }
        std::printf("%.17g %.17g %.17g %.17g\n", v, xi, alpha, damping);
    }
    return failures;
}
