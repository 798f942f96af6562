//! The stand-ins of a student's functions in another language: a JavaScript file the
//! harness loads as it loads a student's, whose top level evaluates the student's file
//! afresh in its interpreter and whose functions call the interpreter's (`bridge.js`), and
//! the host functions they call, installed in the phase's engine.

use super::super::cpu::CpuClock;
use super::interpreter::Interpreter;
use labs::grading::Job;
use rquickjs::{Ctx, Function};
use std::cell::RefCell;
use std::collections::BTreeSet;
use std::rc::Rc;

const BRIDGE_JS: &str = include_str!("bridge.js");

/// A phase's interpreter, as its engine's host functions reach it.
pub struct Bridge {
    interpreter: Rc<RefCell<Interpreter>>,
}

impl Bridge {
    pub fn new(interpreter: Interpreter) -> Bridge {
        Bridge {
            interpreter: Rc::new(RefCell::new(interpreter)),
        }
    }

    /// The interpreter's CPU clock.
    pub fn clock(&self) -> CpuClock {
        self.interpreter.borrow().clock()
    }

    /// Installs `estlabNative` in the engine: every wait for the interpreter looks at
    /// `over`, which says when the phase's time has run out, and `halt` is told why, when
    /// the student's code made the interpreter stop answering (the phase ends there).
    pub fn install(
        &self,
        ctx: &Ctx<'_>,
        over: Rc<dyn Fn() -> bool>,
        halt: Rc<dyn Fn(String)>,
    ) -> rquickjs::Result<()> {
        let ask = {
            let interpreter = Rc::clone(&self.interpreter);
            move |request: &dyn Fn(&mut Interpreter, &dyn Fn() -> bool) -> String| {
                let mut interpreter = interpreter.borrow_mut();
                let reply = request(&mut interpreter, &*over);
                if let Some(reason) = interpreter.stopped() {
                    halt(reason);
                }
                reply
            }
        };
        let ask = Rc::new(ask);
        let asked = Rc::clone(&ask);
        let load = Function::new(ctx.clone(), move || {
            asked(&|interpreter, over| interpreter.load(over))
        })?;
        let call = Function::new(ctx.clone(), move |name: String, args: String| {
            let args: Vec<serde_json::Value> = serde_json::from_str(&args).unwrap_or_default();
            ask(&|interpreter, over| interpreter.call(&name, &args, over))
        })?;
        ctx.globals().set("estlabNativeLoad", load)?;
        ctx.globals().set("estlabNativeCall", call)?;
        ctx.eval::<(), _>(BRIDGE_JS)
    }

    /// The stand-in file for the functions `job` calls.
    pub fn stand_ins(job: &Job) -> String {
        let names: BTreeSet<&str> = job
            .functions
            .iter()
            .map(|phase| phase.function.as_str())
            .chain(
                job.runs
                    .iter()
                    .flat_map(|run| run.functions.iter().map(String::as_str)),
            )
            .collect();
        let mut file = String::from("var estlabDefined = estlabNative.load();\n");
        for name in names {
            file += &format!(
                "var {name} = estlabDefined.{name} ? function () {{ return estlabNative.call('{name}', arguments); }} : undefined;\n"
            );
        }
        file
    }
}
