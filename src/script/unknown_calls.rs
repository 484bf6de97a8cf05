//! `check` for calls of functions and methods no one provides: every call in a script
//! (its functions' and closures' bodies included) must name a function of the drive API,
//! of Rhai's standard library or of the script itself (wherever it is defined), a Rhai
//! keyword function (`Fn`, `call`, `curry`, `type_of`, …), or a variable or map property
//! that may hold a function pointer. Others are located problems with did-you-mean from
//! the API's and the script's names, so a misspelt `d.sampel(…)` is found before the drive
//! is enabled rather than at its line. Only names are judged (not argument counts or
//! types); it must not run the script.

use super::script_error::span_at;
use crate::diag::{did_you_mean, suggestion_text, Diagnostic, Source};
use rhai::{ASTNode, Engine, Expr, FnCallExpr, Position, Stmt, AST};
use std::collections::HashSet;
use std::sync::Arc;

/// Functions the engine handles itself rather than through a registered function.
const KEYWORD_FUNCTIONS: [&str; 9] = [
    "print",
    "debug",
    "type_of",
    "Fn",
    "call",
    "curry",
    "is_shared",
    "is_def_var",
    "is_def_fn",
];

/// The problems of `ast`'s calls; `engine` is the sandbox with the drive API registered.
pub fn unknown_calls(ast: &AST, engine: &Engine, source: &Arc<Source>) -> Vec<Diagnostic> {
    let mut calls: Vec<(String, bool, Position)> = Vec::new();
    let mut holders: HashSet<String> = HashSet::new();
    ast.walk(&mut |path: &[ASTNode]| {
        match path.last() {
            Some(ASTNode::Expr(Expr::FnCall(f, pos))) | Some(ASTNode::Stmt(Stmt::FnCall(f, pos))) => {
                push_call(&mut calls, f, false, *pos);
            }
            Some(ASTNode::Expr(Expr::MethodCall(f, pos))) => push_call(&mut calls, f, true, *pos),
            Some(ASTNode::Expr(Expr::Variable(v, _, _))) => {
                holders.insert(v.1.to_string());
            }
            Some(ASTNode::Expr(Expr::Property(p, _))) => {
                holders.insert(p.2.to_string());
            }
            Some(ASTNode::Expr(Expr::Map(m, _))) => {
                holders.extend(m.0.iter().map(|(k, _)| k.name.to_string()));
            }
            // A map written with constants only (closures included) is one constant.
            Some(ASTNode::Expr(Expr::DynamicConstant(v, _))) => {
                if let Some(map) = v.read_lock::<rhai::Map>() {
                    holders.extend(map.keys().map(|k| k.to_string()));
                }
            }
            Some(ASTNode::Stmt(Stmt::Var(v, _, _))) => {
                holders.insert(v.0.name.to_string());
            }
            _ => {}
        }
        true
    });
    // Function bodies are walked after the main statements: report in the text's order.
    calls.sort_by_key(|(_, _, pos)| (pos.line(), pos.position()));
    let script_fns: Vec<String> = ast.iter_functions().map(|f| f.name.to_string()).collect();
    for f in ast.iter_functions() {
        holders.extend(f.params.iter().map(|p| p.to_string()));
    }
    let api = engine.collect_fn_metadata(None, |f| Some(f.metadata.name.to_string()), false);
    let everything = engine.collect_fn_metadata(None, |f| Some(f.metadata.name.to_string()), true);
    let known: HashSet<&str> = everything
        .iter()
        .chain(&script_fns)
        .map(String::as_str)
        .chain(KEYWORD_FUNCTIONS)
        .collect();
    let ours: Vec<&str> = api
        .iter()
        .chain(&script_fns)
        .map(String::as_str)
        .filter(|n| is_name(n) && !n.starts_with("anon"))
        .collect();
    let mut problems = Vec::new();
    for (name, method, pos) in calls {
        if known.contains(name.as_str()) || holders.contains(&name) {
            continue;
        }
        let kind = if method { "method" } else { "function" };
        let message = format!(
            "unknown {kind} `{name}`: neither the drive API, the script nor Rhai's standard library has it"
        );
        // The drive API's and the script's names first; Rhai's library (hundreds of names)
        // only when none is close, beside what a script can call at all.
        let help = suggestion_text(&did_you_mean(&name, ours.iter().copied())).unwrap_or_else(|| {
            let library = did_you_mean(&name, known.iter().copied().filter(|n| is_name(n)));
            let what = "a script calls the drive API (listed in the README, Rhai scripts), its own functions and Rhai's standard library; it has no file, process or module access";
            match suggestion_text(&library) {
                Some(s) => format!("{s} {what}"),
                None => what.to_string(),
            }
        });
        let label = if method {
            "unknown method"
        } else {
            "unknown function"
        };
        let d = match span_at(source, pos) {
            Some(span) => Diagnostic::at(&span, message, label),
            None => Diagnostic::unlocated(source.path(), message),
        };
        problems.push(d.with_help(help));
    }
    problems
}

fn push_call(calls: &mut Vec<(String, bool, Position)>, f: &FnCallExpr, method: bool, pos: Position) {
    // Operators (`+`, `..`, `!`) are calls too, of functions Rhai provides.
    if f.is_operator_call() || f.op_token.is_some() || !is_name(&f.name) {
        return;
    }
    calls.push((f.name.to_string(), method, pos));
}

/// A name a script can write (not an operator or an engine-internal name like `get$x`).
fn is_name(name: &str) -> bool {
    name.chars().next().is_some_and(|c| c.is_alphabetic() || c == '_')
        && name.chars().all(|c| c.is_alphanumeric() || c == '_')
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::family::Registry;
    use crate::script::sandbox::sandbox;

    fn problems(text: &str) -> Vec<String> {
        let dictionary = crate::run::DictionaryArgs::builtin_default()
            .load_for(&Registry::builtin(), None)
            .expect("the built-in dictionary");
        let source = Source::new("s.rhai", text);
        let ast = sandbox().compile(text).expect("syntax");
        let mut engine = sandbox();
        super::super::drive_api::register(
            &mut engine,
            &Arc::new(super::super::bridge::Bridge::detached(dictionary)),
        );
        unknown_calls(&ast, &engine, &source)
            .iter()
            .map(|d| format!("{} | {}", d.located(), d.help().unwrap_or_default()))
            .collect()
    }

    #[test]
    fn what_rhai_and_the_script_provide_is_not_a_problem() {
        let script = r#"
            let d = drive();
            let s = "Hello, drive";
            let t = s.to_upper().sub_string(1, 2) + s.len().to_string();
            let parts = "a,b".split(",");
            let a = [3, 1, 2];
            a.sort();
            a.push(4);
            let m = a.map(|x| x * 2).filter(|x| x > 2).reduce(|sum, x| sum + x, 0);
            let mp = #{ a: 1, act: |x| x + 1 };
            let k = mp.keys().len() + mp.values().len();
            let n = mp.act(1) + 2.7.floor().to_int() + abs(-3) + max(1, 2) + parse_int("5");
            let y = sqrt(4.0) + 1.5.round() + to_float(3);
            if "b" in parts && s.contains("drive") { print(`${t}`); debug(m); }
            for i in range(0, 3) { log(i); }
            for i in 0..3 { dwell("1 s"); }
            let f = |x| x + 1;
            let g = Fn("helper");
            let h = f.curry(1);
            let z = f.call(1) + g.call(2) + h.call() + f(4);
            if type_of(h) == "Fn" && is_def_fn("helper", 1) { fail("no"); }
            let later = helper2(d);
            let w = d.sample(["speed_actual"], "100 ms", "1 s");
            expect("mean", w.mean("speed_actual") > 0.0, w.max("speed_actual"));
            expect_near("p", param("top", 1.0, "rpm"), 1.0, "1 %");
            try { d.fault_reset(); } catch (e) { log(e.to_string()); }
            let ts = timestamp();
            fn helper(x) { x.to_string().len() }
            fn helper2(d) { d.read_as("speed_actual", "rpm") + helper(2) }
            fn finally(d) { d.disable_operation(); d.shutdown(); }
        "#;
        assert_eq!(problems(script), Vec::<String>::new());
    }

    #[test]
    fn misspelt_and_missing_calls_are_found_where_they_are_written() {
        let found = problems("let d = drive();\nlet w = d.sampel([\"speed_actual\"], \"100 ms\", \"1 s\");\nopen_file(\"/etc/passwd\");\nfn f(d) { d.enable_operatoin(); }\nlet x = [1].pussh(2);\n");
        assert_eq!(found.len(), 4, "{found:#?}");
        let starts = [
            "s.rhai:2:11: unknown method `sampel`",
            "s.rhai:3:1: unknown function `open_file`",
            "s.rhai:4:13: unknown method `enable_operatoin`",
        ];
        for (problem, start) in found.iter().zip(starts) {
            assert!(problem.starts_with(start), "{found:#?}");
        }
        assert!(found[0].ends_with("did you mean `sample`?"), "{found:#?}");
        for (i, part) in [
            (1, "no file, process or module access"),
            (2, "did you mean `enable_operation`"),
            (3, "unknown method `pussh`"),
            (3, "did you mean `push`"),
        ] {
            assert!(found[i].contains(part), "{found:#?}");
        }
    }
}
