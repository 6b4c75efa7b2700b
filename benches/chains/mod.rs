//! Chains of n masses for the stability benches and tests: each link (ground–x1,
//! x1–x2, …) a linear + cubic spring with a viscous and a fractional damper of order
//! `p`, `s_i = k y_i + k3 y_i³ + c y_i' + h D^p y_i`, `y_i = x_i − x_{i−1}`; mass `i`:
//! `m x_i'' + s_i − s_{i+1} = 0`, the last one forced by `F cos Ωt`. The four models
//! are the same text for different n (written out: the DSL takes literal equations).
#![allow(dead_code)] // each user takes the chains it needs

ihbm::oscillator! {
    /// A chain of 2 masses (scaling benchmark).
    pub struct Chain2 {
        params { m = 1.0, k = 1.0, k3 = 0.5, c = 0.02, h = 0.02, p = 0.5, F = 0.05 }
        dofs { x1, x2 }
        let y1 = x1;
        let s1 = k * y1 + k3 * y1.powi(3) + c * D(y1, 1) + h * D(y1, p);
        let y2 = x2 - x1;
        let s2 = k * y2 + k3 * y2.powi(3) + c * D(y2, 1) + h * D(y2, p);
        equations {
            m * D(x1, 2) + s1 - s2 = 0.0;
            m * D(x2, 2) + s2 = F * cos(omega * t);
        }
        outputs { x1, x2 }
    }
}

ihbm::oscillator! {
    /// A chain of 5 masses (scaling benchmark).
    pub struct Chain5 {
        params { m = 1.0, k = 1.0, k3 = 0.5, c = 0.02, h = 0.02, p = 0.5, F = 0.05 }
        dofs { x1, x2, x3, x4, x5 }
        let y1 = x1;
        let s1 = k * y1 + k3 * y1.powi(3) + c * D(y1, 1) + h * D(y1, p);
        let y2 = x2 - x1;
        let s2 = k * y2 + k3 * y2.powi(3) + c * D(y2, 1) + h * D(y2, p);
        let y3 = x3 - x2;
        let s3 = k * y3 + k3 * y3.powi(3) + c * D(y3, 1) + h * D(y3, p);
        let y4 = x4 - x3;
        let s4 = k * y4 + k3 * y4.powi(3) + c * D(y4, 1) + h * D(y4, p);
        let y5 = x5 - x4;
        let s5 = k * y5 + k3 * y5.powi(3) + c * D(y5, 1) + h * D(y5, p);
        equations {
            m * D(x1, 2) + s1 - s2 = 0.0;
            m * D(x2, 2) + s2 - s3 = 0.0;
            m * D(x3, 2) + s3 - s4 = 0.0;
            m * D(x4, 2) + s4 - s5 = 0.0;
            m * D(x5, 2) + s5 = F * cos(omega * t);
        }
        outputs { x1, x5 }
    }
}

ihbm::oscillator! {
    /// A chain of 10 masses (scaling benchmark).
    pub struct Chain10 {
        params { m = 1.0, k = 1.0, k3 = 0.5, c = 0.02, h = 0.02, p = 0.5, F = 0.05 }
        dofs { x1, x2, x3, x4, x5, x6, x7, x8, x9, x10 }
        let y1 = x1;
        let s1 = k * y1 + k3 * y1.powi(3) + c * D(y1, 1) + h * D(y1, p);
        let y2 = x2 - x1;
        let s2 = k * y2 + k3 * y2.powi(3) + c * D(y2, 1) + h * D(y2, p);
        let y3 = x3 - x2;
        let s3 = k * y3 + k3 * y3.powi(3) + c * D(y3, 1) + h * D(y3, p);
        let y4 = x4 - x3;
        let s4 = k * y4 + k3 * y4.powi(3) + c * D(y4, 1) + h * D(y4, p);
        let y5 = x5 - x4;
        let s5 = k * y5 + k3 * y5.powi(3) + c * D(y5, 1) + h * D(y5, p);
        let y6 = x6 - x5;
        let s6 = k * y6 + k3 * y6.powi(3) + c * D(y6, 1) + h * D(y6, p);
        let y7 = x7 - x6;
        let s7 = k * y7 + k3 * y7.powi(3) + c * D(y7, 1) + h * D(y7, p);
        let y8 = x8 - x7;
        let s8 = k * y8 + k3 * y8.powi(3) + c * D(y8, 1) + h * D(y8, p);
        let y9 = x9 - x8;
        let s9 = k * y9 + k3 * y9.powi(3) + c * D(y9, 1) + h * D(y9, p);
        let y10 = x10 - x9;
        let s10 = k * y10 + k3 * y10.powi(3) + c * D(y10, 1) + h * D(y10, p);
        equations {
            m * D(x1, 2) + s1 - s2 = 0.0;
            m * D(x2, 2) + s2 - s3 = 0.0;
            m * D(x3, 2) + s3 - s4 = 0.0;
            m * D(x4, 2) + s4 - s5 = 0.0;
            m * D(x5, 2) + s5 - s6 = 0.0;
            m * D(x6, 2) + s6 - s7 = 0.0;
            m * D(x7, 2) + s7 - s8 = 0.0;
            m * D(x8, 2) + s8 - s9 = 0.0;
            m * D(x9, 2) + s9 - s10 = 0.0;
            m * D(x10, 2) + s10 = F * cos(omega * t);
        }
        outputs { x1, x10 }
    }
}

ihbm::oscillator! {
    /// A chain of 20 masses (scaling benchmark).
    pub struct Chain20 {
        params { m = 1.0, k = 1.0, k3 = 0.5, c = 0.02, h = 0.02, p = 0.5, F = 0.05 }
        dofs { x1, x2, x3, x4, x5, x6, x7, x8, x9, x10, x11, x12, x13, x14, x15, x16, x17, x18, x19, x20 }
        let y1 = x1;
        let s1 = k * y1 + k3 * y1.powi(3) + c * D(y1, 1) + h * D(y1, p);
        let y2 = x2 - x1;
        let s2 = k * y2 + k3 * y2.powi(3) + c * D(y2, 1) + h * D(y2, p);
        let y3 = x3 - x2;
        let s3 = k * y3 + k3 * y3.powi(3) + c * D(y3, 1) + h * D(y3, p);
        let y4 = x4 - x3;
        let s4 = k * y4 + k3 * y4.powi(3) + c * D(y4, 1) + h * D(y4, p);
        let y5 = x5 - x4;
        let s5 = k * y5 + k3 * y5.powi(3) + c * D(y5, 1) + h * D(y5, p);
        let y6 = x6 - x5;
        let s6 = k * y6 + k3 * y6.powi(3) + c * D(y6, 1) + h * D(y6, p);
        let y7 = x7 - x6;
        let s7 = k * y7 + k3 * y7.powi(3) + c * D(y7, 1) + h * D(y7, p);
        let y8 = x8 - x7;
        let s8 = k * y8 + k3 * y8.powi(3) + c * D(y8, 1) + h * D(y8, p);
        let y9 = x9 - x8;
        let s9 = k * y9 + k3 * y9.powi(3) + c * D(y9, 1) + h * D(y9, p);
        let y10 = x10 - x9;
        let s10 = k * y10 + k3 * y10.powi(3) + c * D(y10, 1) + h * D(y10, p);
        let y11 = x11 - x10;
        let s11 = k * y11 + k3 * y11.powi(3) + c * D(y11, 1) + h * D(y11, p);
        let y12 = x12 - x11;
        let s12 = k * y12 + k3 * y12.powi(3) + c * D(y12, 1) + h * D(y12, p);
        let y13 = x13 - x12;
        let s13 = k * y13 + k3 * y13.powi(3) + c * D(y13, 1) + h * D(y13, p);
        let y14 = x14 - x13;
        let s14 = k * y14 + k3 * y14.powi(3) + c * D(y14, 1) + h * D(y14, p);
        let y15 = x15 - x14;
        let s15 = k * y15 + k3 * y15.powi(3) + c * D(y15, 1) + h * D(y15, p);
        let y16 = x16 - x15;
        let s16 = k * y16 + k3 * y16.powi(3) + c * D(y16, 1) + h * D(y16, p);
        let y17 = x17 - x16;
        let s17 = k * y17 + k3 * y17.powi(3) + c * D(y17, 1) + h * D(y17, p);
        let y18 = x18 - x17;
        let s18 = k * y18 + k3 * y18.powi(3) + c * D(y18, 1) + h * D(y18, p);
        let y19 = x19 - x18;
        let s19 = k * y19 + k3 * y19.powi(3) + c * D(y19, 1) + h * D(y19, p);
        let y20 = x20 - x19;
        let s20 = k * y20 + k3 * y20.powi(3) + c * D(y20, 1) + h * D(y20, p);
        equations {
            m * D(x1, 2) + s1 - s2 = 0.0;
            m * D(x2, 2) + s2 - s3 = 0.0;
            m * D(x3, 2) + s3 - s4 = 0.0;
            m * D(x4, 2) + s4 - s5 = 0.0;
            m * D(x5, 2) + s5 - s6 = 0.0;
            m * D(x6, 2) + s6 - s7 = 0.0;
            m * D(x7, 2) + s7 - s8 = 0.0;
            m * D(x8, 2) + s8 - s9 = 0.0;
            m * D(x9, 2) + s9 - s10 = 0.0;
            m * D(x10, 2) + s10 - s11 = 0.0;
            m * D(x11, 2) + s11 - s12 = 0.0;
            m * D(x12, 2) + s12 - s13 = 0.0;
            m * D(x13, 2) + s13 - s14 = 0.0;
            m * D(x14, 2) + s14 - s15 = 0.0;
            m * D(x15, 2) + s15 - s16 = 0.0;
            m * D(x16, 2) + s16 - s17 = 0.0;
            m * D(x17, 2) + s17 - s18 = 0.0;
            m * D(x18, 2) + s18 - s19 = 0.0;
            m * D(x19, 2) + s19 - s20 = 0.0;
            m * D(x20, 2) + s20 = F * cos(omega * t);
        }
        outputs { x1, x20 }
    }
}
