//! The `behaviour` argument (core's device behaviour switches, docs/spec/SPEC.md "Device
//! behaviours") and `pointillist.behaviours()`, core's table as Python values.

use pointillist_core::behaviour::{
    BEHAVIOURS, BehaviourDef, BehaviourError, BehaviourSetting, Behaviours, PROFILE_KEY, PROFILES,
};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList, PyString};

use crate::arrays::got;

/// The `behaviour` argument: `None`, or a dict of switch names to options (str to str), each
/// checked against core's table, and perhaps `"profile": NAME`. The settings come in the
/// dict's order, to be applied over a scene's `[behaviour]` table as `--behaviour` is
/// ([`Behaviours::with`]: the profile first).
pub fn settings(obj: Option<&Bound<'_, PyAny>>) -> PyResult<Vec<BehaviourSetting>> {
    let Some(obj) = obj.filter(|o| !o.is_none()) else {
        return Ok(Vec::new());
    };
    let dict = obj.cast::<PyDict>().map_err(|_| {
        PyTypeError::new_err(format!(
            "behaviour must be a dict of switch names to options, such as \
             {{\"minimum_size\": \"one_pixel\"}}, or None; got {}",
            got(obj)
        ))
    })?;
    let names = || {
        let switches = BEHAVIOURS.iter().map(|d| d.name).collect::<Vec<_>>();
        format!("{}, or {PROFILE_KEY}", switches.join(", "))
    };
    let items = dict.items(); // a list: the checks below may run Python code (`repr`)
    let mut out = Vec::with_capacity(items.len());
    for item in items.iter() {
        let (key, value): (Bound<'_, PyAny>, Bound<'_, PyAny>) = item.extract()?;
        let Ok(name) = key.cast::<PyString>() else {
            return Err(PyTypeError::new_err(format!(
                "behaviour key {} is not a str (expected one of: {})",
                got(&key),
                names()
            )));
        };
        let name = name.to_string_lossy();
        let (name, options): (&str, Vec<&str>) = if name == PROFILE_KEY {
            (PROFILE_KEY, PROFILES.iter().map(|p| p.name).collect())
        } else {
            let def = BehaviourDef::find(&name)
                .ok_or_else(|| value_error(BehaviourError::UnknownSwitch(name.to_string())))?;
            (def.name, def.option_names().collect())
        };
        let Ok(option) = value.cast::<PyString>() else {
            return Err(PyTypeError::new_err(format!(
                "behaviour[\"{name}\"] must be a str (expected one of: {}); got {}",
                options.join(", "),
                got(&value)
            )));
        };
        let setting =
            BehaviourSetting::new(name, &option.to_string_lossy()).map_err(value_error)?;
        out.push(setting);
    }
    Ok(out)
}

/// Core's error (which lists the valid names or options), naming the argument.
fn value_error(e: BehaviourError) -> PyErr {
    PyValueError::new_err(format!("behaviour: {e}"))
}

/// The `behaviour` argument of a call that creates its own device: the defaults with the
/// argument's settings.
pub fn behaviours(obj: Option<&Bound<'_, PyAny>>) -> PyResult<Behaviours> {
    Ok(Behaviours::default().with(&settings(obj)?))
}

/// Every switch as ``pointillist behaviours --json`` lists it: a list of dicts with ``name``,
/// ``options``, ``default``, ``evidence``, ``sources``, ``summary``, ``rule`` and
/// ``option_effects`` (what each option draws).
#[pyfunction]
pub fn behaviours_table(py: Python<'_>) -> PyResult<Bound<'_, PyList>> {
    let items = BEHAVIOURS
        .iter()
        .map(|d| {
            let dict = PyDict::new(py);
            dict.set_item("name", d.name)?;
            dict.set_item("options", d.option_names().collect::<Vec<_>>())?;
            dict.set_item("default", d.default_name())?;
            dict.set_item("evidence", d.evidence.name())?;
            dict.set_item("sources", d.sources.to_vec())?;
            dict.set_item("summary", d.summary)?;
            dict.set_item("rule", d.rule)?;
            let effects = PyDict::new(py);
            for (option, what) in d.options {
                effects.set_item(option, what)?;
            }
            dict.set_item("option_effects", effects)?;
            Ok(dict)
        })
        .collect::<PyResult<Vec<_>>>()?;
    PyList::new(py, items)
}

/// Every profile as ``pointillist behaviours --profiles --json`` lists it: a list of dicts
/// with ``name``, ``summary``, ``settings`` (a dict of switch names to options) and
/// ``sources``.
#[pyfunction]
pub fn behaviour_profiles(py: Python<'_>) -> PyResult<Bound<'_, PyList>> {
    let items = PROFILES
        .iter()
        .map(|p| {
            let dict = PyDict::new(py);
            dict.set_item("name", p.name)?;
            dict.set_item("summary", p.summary)?;
            let settings = PyDict::new(py);
            for (switch, option) in p.settings {
                settings.set_item(switch, option)?;
            }
            dict.set_item("settings", settings)?;
            dict.set_item("sources", p.sources.to_vec())?;
            Ok(dict)
        })
        .collect::<PyResult<Vec<_>>>()?;
    PyList::new(py, items)
}

/// The option of every switch `b` holds, as a dict (``Device.behaviour``).
pub fn as_dict<'py>(py: Python<'py>, b: &Behaviours) -> PyResult<Bound<'py, PyDict>> {
    let dict = PyDict::new(py);
    for (def, option) in b.iter() {
        dict.set_item(def.name, option)?;
    }
    Ok(dict)
}
