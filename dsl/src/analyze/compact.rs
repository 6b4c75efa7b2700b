//! Compaction: only what the residual uses is kept. Aliases reachable from an equation
//! are marked used, and the signals are renumbered in order of first use (equations
//! left to right, an alias where it is first used), so a signal met only in an unused
//! alias is dropped and the generated code reads the signal slice in order.

use super::tree::{Alias, Analysis, Node};

/// Mark used aliases and list signals in order of first use, then renumber.
pub fn compact(a: &mut Analysis) {
    fn walk(n: &Node, aliases: &mut [Alias], order: &mut Vec<usize>) {
        match n {
            Node::Signal(s) => {
                if !order.contains(s) {
                    order.push(*s);
                }
            }
            Node::Alias(i) => {
                if !aliases[*i].used {
                    aliases[*i].used = true;
                    let inner = aliases[*i].node.clone();
                    walk(&inner, aliases, order);
                }
            }
            other => other.for_each_child(|c| walk(c, aliases, order)),
        }
    }
    fn renumber(n: &mut Node, map: &[Option<usize>]) {
        match n {
            Node::Signal(s) => {
                if let Some(Some(new)) = map.get(*s) {
                    *s = *new;
                }
            }
            other => other.for_each_child_mut(|c| renumber(c, map)),
        }
    }
    let mut order = Vec::new();
    for eq in &a.equations {
        walk(eq, &mut a.aliases, &mut order);
    }
    let mut map = vec![None; a.signals.len()];
    for (new, old) in order.iter().enumerate() {
        map[*old] = Some(new);
    }
    a.signals = order.iter().map(|i| a.signals[*i].clone()).collect();
    for eq in &mut a.equations {
        renumber(eq, &map);
    }
    for alias in &mut a.aliases {
        if alias.used {
            renumber(&mut alias.node, &map);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analyze::tree::{OrderKey, SignalKey};

    fn key(dof: usize) -> SignalKey {
        SignalKey { terms: vec![(dof, 1.0)], order: OrderKey::Int(0) }
    }
    fn b(n: Node) -> Box<Node> {
        Box::new(n)
    }

    #[test]
    fn signals_are_renumbered_by_first_use_and_unused_aliases_dropped() {
        // Signals 0..4; alias 0 = s1 * s3, alias 1 = s0 (unused), alias 2 = alias 0 + s2.
        // Equation 0: s2 + alias 2; equation 1: s3 - s2.
        let mut a = Analysis {
            signals: (0..4).map(key).collect(),
            aliases: vec![
                Alias { node: Node::Mul(b(Node::Signal(1)), b(Node::Signal(3))), used: false },
                Alias { node: Node::Signal(0), used: false },
                Alias { node: Node::Add(b(Node::Alias(0)), b(Node::Signal(2))), used: false },
            ],
            equations: vec![
                Node::Add(b(Node::Signal(2)), b(Node::Alias(2))),
                Node::Sub(b(Node::Signal(3)), b(Node::Signal(2))),
            ],
            outputs: Vec::new(),
            output_signals: Vec::new(),
            output_exprs: Vec::new(),
            checks: Vec::new(),
        };
        compact(&mut a);
        // First use: s2 (eq 0), then inside alias 2 → alias 0: s1, s3. s0 is never used.
        let dofs: Vec<usize> = a.signals.iter().map(|s| s.terms[0].0).collect();
        assert_eq!(dofs, [2, 1, 3]);
        let used: Vec<bool> = a.aliases.iter().map(|x| x.used).collect();
        assert_eq!(used, [true, false, true]);
        let signal_of = |n: &Node| match n {
            Node::Signal(s) => *s,
            _ => unreachable!(),
        };
        match &a.aliases[0].node {
            Node::Mul(x, y) => assert_eq!((signal_of(x), signal_of(y)), (1, 2)),
            _ => unreachable!(),
        }
        match &a.equations[1] {
            Node::Sub(x, y) => assert_eq!((signal_of(x), signal_of(y)), (2, 0)),
            _ => unreachable!(),
        }
        // The unused alias keeps its old number: it is never emitted.
        assert!(matches!(a.aliases[1].node, Node::Signal(0)));
    }
}
