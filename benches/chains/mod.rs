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

ihbm::oscillator! {
    /// A chain of 40 masses (the sparse-factorisation benchmark).
    pub struct Chain40 {
        params { m = 1.0, k = 1.0, k3 = 0.5, c = 0.02, h = 0.02, p = 0.5, F = 0.05 }
        dofs { x1, x2, x3, x4, x5, x6, x7, x8, x9, x10, x11, x12, x13, x14, x15, x16, x17, x18, x19, x20, x21, x22, x23, x24, x25, x26, x27, x28, x29, x30, x31, x32, x33, x34, x35, x36, x37, x38, x39, x40 }
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
        let y21 = x21 - x20;
        let s21 = k * y21 + k3 * y21.powi(3) + c * D(y21, 1) + h * D(y21, p);
        let y22 = x22 - x21;
        let s22 = k * y22 + k3 * y22.powi(3) + c * D(y22, 1) + h * D(y22, p);
        let y23 = x23 - x22;
        let s23 = k * y23 + k3 * y23.powi(3) + c * D(y23, 1) + h * D(y23, p);
        let y24 = x24 - x23;
        let s24 = k * y24 + k3 * y24.powi(3) + c * D(y24, 1) + h * D(y24, p);
        let y25 = x25 - x24;
        let s25 = k * y25 + k3 * y25.powi(3) + c * D(y25, 1) + h * D(y25, p);
        let y26 = x26 - x25;
        let s26 = k * y26 + k3 * y26.powi(3) + c * D(y26, 1) + h * D(y26, p);
        let y27 = x27 - x26;
        let s27 = k * y27 + k3 * y27.powi(3) + c * D(y27, 1) + h * D(y27, p);
        let y28 = x28 - x27;
        let s28 = k * y28 + k3 * y28.powi(3) + c * D(y28, 1) + h * D(y28, p);
        let y29 = x29 - x28;
        let s29 = k * y29 + k3 * y29.powi(3) + c * D(y29, 1) + h * D(y29, p);
        let y30 = x30 - x29;
        let s30 = k * y30 + k3 * y30.powi(3) + c * D(y30, 1) + h * D(y30, p);
        let y31 = x31 - x30;
        let s31 = k * y31 + k3 * y31.powi(3) + c * D(y31, 1) + h * D(y31, p);
        let y32 = x32 - x31;
        let s32 = k * y32 + k3 * y32.powi(3) + c * D(y32, 1) + h * D(y32, p);
        let y33 = x33 - x32;
        let s33 = k * y33 + k3 * y33.powi(3) + c * D(y33, 1) + h * D(y33, p);
        let y34 = x34 - x33;
        let s34 = k * y34 + k3 * y34.powi(3) + c * D(y34, 1) + h * D(y34, p);
        let y35 = x35 - x34;
        let s35 = k * y35 + k3 * y35.powi(3) + c * D(y35, 1) + h * D(y35, p);
        let y36 = x36 - x35;
        let s36 = k * y36 + k3 * y36.powi(3) + c * D(y36, 1) + h * D(y36, p);
        let y37 = x37 - x36;
        let s37 = k * y37 + k3 * y37.powi(3) + c * D(y37, 1) + h * D(y37, p);
        let y38 = x38 - x37;
        let s38 = k * y38 + k3 * y38.powi(3) + c * D(y38, 1) + h * D(y38, p);
        let y39 = x39 - x38;
        let s39 = k * y39 + k3 * y39.powi(3) + c * D(y39, 1) + h * D(y39, p);
        let y40 = x40 - x39;
        let s40 = k * y40 + k3 * y40.powi(3) + c * D(y40, 1) + h * D(y40, p);
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
            m * D(x20, 2) + s20 - s21 = 0.0;
            m * D(x21, 2) + s21 - s22 = 0.0;
            m * D(x22, 2) + s22 - s23 = 0.0;
            m * D(x23, 2) + s23 - s24 = 0.0;
            m * D(x24, 2) + s24 - s25 = 0.0;
            m * D(x25, 2) + s25 - s26 = 0.0;
            m * D(x26, 2) + s26 - s27 = 0.0;
            m * D(x27, 2) + s27 - s28 = 0.0;
            m * D(x28, 2) + s28 - s29 = 0.0;
            m * D(x29, 2) + s29 - s30 = 0.0;
            m * D(x30, 2) + s30 - s31 = 0.0;
            m * D(x31, 2) + s31 - s32 = 0.0;
            m * D(x32, 2) + s32 - s33 = 0.0;
            m * D(x33, 2) + s33 - s34 = 0.0;
            m * D(x34, 2) + s34 - s35 = 0.0;
            m * D(x35, 2) + s35 - s36 = 0.0;
            m * D(x36, 2) + s36 - s37 = 0.0;
            m * D(x37, 2) + s37 - s38 = 0.0;
            m * D(x38, 2) + s38 - s39 = 0.0;
            m * D(x39, 2) + s39 - s40 = 0.0;
            m * D(x40, 2) + s40 = F * cos(omega * t);
        }
        outputs { x1, x40 }
    }
}
