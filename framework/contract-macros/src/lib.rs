//! `#[contract]` on a lab contract's trait: the code every contract needs and no one should
//! write by hand.
//!
//! For `#[contract] pub trait Shadows: Send + Sync { fn shadow_ray(&self, …) -> Ray; … }` it
//! keeps the trait as written and adds
//!
//! - `impl<C: ?Sized + Shadows> Shadows for PartSlot<C>`: each method sent to the
//!   implementation [`PartSlot::pick`] gives for that method's name — the student's for the
//!   methods a check puts in the slot, the base's for every other — so that one unfinished
//!   exercise never fails another;
//! - `impl Mix for dyn Shadows`: the student's code with the key in place of some methods, which
//!   the grader judges an exercise with when the exercises of the other methods it calls fail;
//! - `impl Shadows for Waiting<dyn Shadows>`: every method panics, saying that it waits for
//!   the lab's solution (the slot of a lab whose answer key the tree does not hold);
//! - `impl<C: ?Sized + Shadows> Shadows for Traced<C>` and `impl Trace for dyn Shadows`: the
//!   code with its every call noted while the pixel inspector records on the calling thread
//!   (`contracts::trace`): lab, trait and method, each argument and the result by `Debug`
//!   (a closure argument as `<closure>`), the depth of nested calls, a panic (noted, then
//!   resumed) and a NaN or infinite result. When nothing records, a traced method costs one
//!   relaxed atomic load before it forwards the call; the contract's argument and result types
//!   must implement `Debug`;
//! - `impl ContractMethods for dyn Shadows`: the names of the trait's methods, which the tests
//!   compare with the functions of the lab's exercise table;
//! - the wire code (`wire.rs`): `impl Shadows for wire::Remote<C>` (each call encoded and run
//!   by a transport on code apart from the checks) and `impl wire::Serves<dyn Shadows>` and
//!   `wire::Serve` (an encoded call run on an implementation, on the student's side).
//!
//! The paths are the `contracts` crate's own (`crate::PartSlot`): the attribute is for that
//! crate's traits. A contract's shape is simple, and the parser here reads that shape only:
//! no generics, methods without bodies that take `&self` and name each argument.

use proc_macro::{Delimiter, Group, Ident, Literal, Punct, Spacing, Span, TokenStream, TokenTree};

mod wire;

/// See the crate's documentation.
#[proc_macro_attribute]
pub fn contract(attr: TokenStream, item: TokenStream) -> TokenStream {
    let expanded = register_path(attr).and_then(|register| expand(item.clone(), &register));
    match expanded {
        Ok(extra) => item.into_iter().chain(extra).collect(),
        Err((message, span)) => compile_error(&message, span),
    }
}

type Expansion = Result<TokenStream, (String, Span)>;

/// The function `#[contract(register = path)]` names, which puts a contract's code under the
/// renderer's extension points besides its own type; empty for `#[contract]`.
fn register_path(attr: TokenStream) -> Result<String, (String, Span)> {
    let tokens: Vec<TokenTree> = attr.into_iter().collect();
    if tokens.is_empty() {
        return Ok(String::new());
    }
    let usage = "#[contract] takes nothing or `register = path::to::function`";
    match tokens.as_slice() {
        [TokenTree::Ident(key), TokenTree::Punct(eq), path @ ..]
            if key.to_string() == "register" && eq.as_char() == '=' && !path.is_empty() =>
        {
            Ok(path.iter().map(ToString::to_string).collect())
        }
        _ => Err((usage.into(), Span::call_site())),
    }
}

/// The impls for the trait `item`; `register` is [`register_path`]'s.
fn expand(item: TokenStream, register: &str) -> Expansion {
    let tokens: Vec<TokenTree> = item.into_iter().collect();
    let trait_at = tokens
        .iter()
        .position(|t| is_ident(t, "trait"))
        .ok_or_else(|| ("#[contract] goes on a trait".to_string(), Span::call_site()))?;
    let name = match tokens.get(trait_at + 1) {
        Some(TokenTree::Ident(name)) => name.clone(),
        _ => {
            return Err((
                "a contract trait needs a name".into(),
                tokens[trait_at].span(),
            ));
        }
    };
    if let Some(TokenTree::Punct(p)) = tokens.get(trait_at + 2)
        && p.as_char() == '<'
    {
        return Err((
            "a contract has no generic parameters: a check holds it as `dyn Trait`".into(),
            p.span(),
        ));
    }
    let body = match tokens.last() {
        Some(TokenTree::Group(g)) if g.delimiter() == Delimiter::Brace => g.clone(),
        _ => return Err(("a contract trait needs a body".into(), name.span())),
    };

    let mut forwards = TokenStream::new();
    let mut waiting = TokenStream::new();
    let mut traced = TokenStream::new();
    let mut names = Vec::new();
    let mut wire_methods = Vec::new();
    for method in split(body.stream(), ';') {
        let method = strip_attributes(method);
        if method.is_empty() {
            continue;
        }
        let (ident, params) = signature(&method)?;
        let args = argument_names(params.clone())?;
        let params: Vec<Vec<TokenTree>> = split(params.stream(), ',').into_iter().skip(1).collect();
        traced.extend(parse("#[inline]"));
        traced.extend(method.clone());
        traced.extend([TokenTree::Group(Group::new(
            Delimiter::Brace,
            parse(&traced_body(
                &name.to_string(),
                &ident.to_string(),
                &args,
                &params,
            )),
        ))]);
        wire_methods.push(wire::WireMethod::new(
            ident.to_string(),
            method.clone(),
            &params,
        )?);
        let mut call =
            format!("self.pick(\"{ident}\", const {{ crate::method_bit(\"{ident}\") }}).{ident}(");
        for arg in &args {
            call.push_str(&format!("{arg},"));
        }
        call.push(')');
        waiting.extend(parse("#[allow(unused_variables)]"));
        waiting.extend(method.clone());
        waiting.extend([TokenTree::Group(Group::new(
            Delimiter::Brace,
            parse(&format!("self.unavailable(\"{ident}\")")),
        ))]);
        forwards.extend(parse("#[inline]"));
        forwards.extend(method);
        forwards.extend([TokenTree::Group(Group::new(Delimiter::Brace, parse(&call)))]);
        names.push(ident.to_string());
    }

    let mut out = parse(&format!(
        "impl<C: ?Sized + {name}> {name} for crate::PartSlot<C>"
    ));
    out.extend([TokenTree::Group(Group::new(Delimiter::Brace, forwards))]);
    out.extend(parse(&format!(
        "impl {name} for crate::Waiting<dyn {name}>"
    )));
    out.extend([TokenTree::Group(Group::new(Delimiter::Brace, waiting))]);
    out.extend(parse(&format!(
        "impl<C: ?Sized + {name}> {name} for crate::Traced<C>"
    )));
    out.extend([TokenTree::Group(Group::new(Delimiter::Brace, traced))]);
    out.extend(parse(&format!(
        "impl crate::Trace for dyn {name} {{ \
           fn trace(code: &::std::sync::Arc<Self>) -> ::std::sync::Arc<Self> {{ \
             ::std::sync::Arc::new(crate::Traced::new(code.clone())) }} }}"
    )));
    let list: Vec<String> = names.iter().map(|n| format!("{n:?}")).collect();
    out.extend(parse(&format!(
        "impl crate::ContractMethods for dyn {name} {{ const METHODS: &'static [&'static str] = &[{}]; }}",
        list.join(", ")
    )));
    out.extend(parse(&format!(
        "impl crate::Mix for dyn {name} {{ \
           fn mix(student: &::std::sync::Arc<Self>, key: &::std::sync::Arc<Self>, \
                  key_for: ::std::vec::Vec<&'static str>, calls: &::std::sync::Arc<crate::CallLog>) \
                  -> ::std::sync::Arc<Self> {{ crate::PartSlot::mixed(student, key, key_for, calls) }} \
           fn only(function: &'static str, student: &::std::sync::Arc<Self>, base: &::std::sync::Arc<Self>) \
                  -> ::std::sync::Arc<Self> {{ crate::PartSlot::shared(function, student, base) }} }}"
    )));
    let also = if register.is_empty() {
        String::new()
    } else {
        format!("{register}(code, parts);")
    };
    out.extend(parse(&format!(
        "impl crate::Part for dyn {name} {{ \
           fn register(code: ::std::sync::Arc<Self>, parts: &mut crate::Parts) {{ \
             parts.put::<Self>(code.clone()); {also} }} }}"
    )));
    out.extend(wire::expand(&name.to_string(), &wire_methods)?);
    Ok(out)
}

/// The body of a method of `impl Trait for Traced<C>`: the call forwarded, and noted while
/// this thread records (`contracts::trace`). `params` are the parameters after `&self`.
fn traced_body(contract: &str, method: &str, args: &[Ident], params: &[Vec<TokenTree>]) -> String {
    let forwarded = format!(
        "crate::Traced::code(self).{method}({})",
        args.iter().map(|a| format!("{a},")).collect::<String>()
    );
    let mut arguments = String::new();
    for (arg, param) in args.iter().zip(params) {
        // `name: &dyn Fn…` or `name: &mut dyn FnMut…`: a closure, which has no `Debug`.
        let closure = param.iter().take(5).any(|t| is_ident(t, "dyn"));
        arguments.push_str(&if closure {
            format!("crate::trace::Argument::closure(\"{arg}\"),")
        } else {
            format!("crate::trace::Argument::of(\"{arg}\", &{arg}),")
        });
    }
    format!(
        "if !crate::trace::is_recording() {{ return {forwarded}; }} \
         let open_call = crate::trace::begin_call( \
             const {{ crate::trace::lab_of_module(::core::module_path!()) }}, \
             \"{contract}\", \"{method}\", ::std::vec![{arguments}]); \
         open_call.finish(::std::panic::catch_unwind(::std::panic::AssertUnwindSafe(|| {forwarded})))"
    )
}

/// A method's name and its parameter list, checked to be `fn name(&self, …) -> …` with no
/// generics and no body.
fn signature(method: &[TokenTree]) -> Result<(Ident, Group), (String, Span)> {
    let shape = "a contract holds methods only, `fn name(&self, …) -> …;`: one per function a student writes";
    let (Some(TokenTree::Ident(fn_)), Some(TokenTree::Ident(ident))) =
        (method.first(), method.get(1))
    else {
        return Err((shape.into(), method[0].span()));
    };
    if fn_.to_string() != "fn" {
        return Err((shape.into(), fn_.span()));
    }
    let params = match method.get(2) {
        Some(TokenTree::Group(g)) if g.delimiter() == Delimiter::Parenthesis => g.clone(),
        Some(other) => {
            return Err((
                "a contract's methods have no generic parameters".into(),
                other.span(),
            ));
        }
        None => return Err((shape.into(), ident.span())),
    };
    if let Some(TokenTree::Group(g)) = method.last()
        && g.delimiter() == Delimiter::Brace
    {
        return Err((
            "a contract's methods have no default bodies: the student writes each".into(),
            g.span(),
        ));
    }
    Ok((ident.clone(), params))
}

/// The names of the arguments after `&self`.
fn argument_names(params: Group) -> Result<Vec<Ident>, (String, Span)> {
    let mut parts = split(params.stream(), ',').into_iter();
    let receiver = parts.next().unwrap_or_default();
    let is_ref_self = matches!(
        receiver.as_slice(),
        [TokenTree::Punct(amp), TokenTree::Ident(s)] if amp.as_char() == '&' && s.to_string() == "self"
    );
    if !is_ref_self {
        return Err((
            "a contract's methods take `&self`: a pipeline shares one implementation between threads".into(),
            params.span(),
        ));
    }
    let mut names = Vec::new();
    for part in parts {
        match part.as_slice() {
            [] => {} // a trailing comma
            [TokenTree::Ident(name), TokenTree::Punct(colon), ..]
                if colon.as_char() == ':' && name.to_string() != "mut" =>
            {
                names.push(name.clone())
            }
            other => {
                return Err((
                    "name each argument of a contract method with a plain identifier".into(),
                    other[0].span(),
                ));
            }
        }
    }
    Ok(names)
}

/// `tokens` split at each `separator` outside brackets (groups) and angle brackets, keeping
/// `->` whole.
fn split(tokens: TokenStream, separator: char) -> Vec<Vec<TokenTree>> {
    let mut parts = vec![Vec::new()];
    let mut angle_depth = 0usize;
    let mut after_minus = false;
    for token in tokens {
        if let TokenTree::Punct(p) = &token {
            let c = p.as_char();
            match c {
                '<' => angle_depth += 1,
                '>' if !after_minus => angle_depth = angle_depth.saturating_sub(1),
                _ => {}
            }
            after_minus = c == '-' && p.spacing() == Spacing::Joint;
            if c == separator && angle_depth == 0 {
                parts.push(Vec::new());
                continue;
            }
        } else {
            after_minus = false;
        }
        parts.last_mut().expect("never empty").push(token);
    }
    parts
}

/// `tokens` without the outer attributes (doc comments among them) in front.
fn strip_attributes(tokens: Vec<TokenTree>) -> Vec<TokenTree> {
    let mut rest = tokens.as_slice();
    while let [TokenTree::Punct(hash), TokenTree::Group(g), tail @ ..] = rest
        && hash.as_char() == '#'
        && g.delimiter() == Delimiter::Bracket
    {
        rest = tail;
    }
    rest.to_vec()
}

fn is_ident(token: &TokenTree, word: &str) -> bool {
    matches!(token, TokenTree::Ident(i) if i.to_string() == word)
}

fn parse(code: &str) -> TokenStream {
    code.parse().expect("the macro's own code parses")
}

fn compile_error(message: &str, span: Span) -> TokenStream {
    let mut tokens = parse("::core::compile_error!");
    let mut literal = Literal::string(message);
    literal.set_span(span);
    let mut arg = Group::new(
        Delimiter::Parenthesis,
        TokenStream::from(TokenTree::Literal(literal)),
    );
    arg.set_span(span);
    tokens.extend([
        TokenTree::Group(arg),
        TokenTree::Punct(Punct::new(';', Spacing::Alone)),
    ]);
    tokens
}

/// The labs whose module file `src/labNN.rs` the crate being compiled holds, in order. Only
/// files inside the crate's own package are read: units that trees of the same layout share in
/// one target directory (the grader's) then never depend on another tree's files.
fn lab_files(input: TokenStream) -> Result<Vec<String>, String> {
    if !input.is_empty() {
        return Err("takes no arguments".into());
    }
    let manifest =
        std::env::var("CARGO_MANIFEST_DIR").map_err(|_| "CARGO_MANIFEST_DIR is not set")?;
    let src = std::path::Path::new(&manifest).join("src");
    let entries = std::fs::read_dir(&src).map_err(|e| format!("{}: {e}", src.display()))?;
    let mut labs: Vec<String> = entries
        .filter_map(|entry| entry.ok()?.file_name().into_string().ok())
        .filter_map(|name| {
            let lab = name.strip_suffix(".rs")?;
            let digits = lab.strip_prefix("lab")?;
            (digits.len() == 2 && digits.bytes().all(|b| b.is_ascii_digit()) && digits != "00")
                .then(|| lab.to_string())
        })
        .collect();
    labs.sort();
    Ok(labs)
}

/// `lab_modules!()` in the contracts crate's `lib.rs`: `pub mod labNN;` for every lab contract
/// `src/labNN.rs` (one per lab of the registry `labs/course.toml`: `tests/tests/course.rs`
/// checks it), and `LABS`, each lab with its waiting slot, so that a new lab's contract needs
/// no line there. The crate's build script has
/// cargo rebuild it when a file comes or goes.
#[proc_macro]
pub fn lab_modules(input: TokenStream) -> TokenStream {
    match lab_files(input) {
        Ok(labs) => {
            let modules: String = labs.iter().map(|lab| format!("pub mod {lab};")).collect();
            let entries: Vec<String> = labs
                .iter()
                .map(|lab| {
                    let number = lab[3..].trim_start_matches('0');
                    format!(
                        "crate::LabParts {{ lab: {number}, waiting: |parts: &mut crate::Parts| \
                         parts.insert::<{lab}::Contract>(::std::sync::Arc::new(\
                         crate::Waiting::<{lab}::Contract>::new({number}))), \
                         remove: |parts: &mut crate::Parts| parts.remove_part::<{lab}::Contract>() }}"
                    )
                })
                .collect();
            parse(&format!(
                "{modules} /// The course's labs in order, each with the slot that waits for its \
                 solution: one per contract file, generated.\n\
                 pub const LABS: &[crate::LabParts] = &[{}];",
                entries.join(", ")
            ))
        }
        Err(message) => compile_error(&format!("lab_modules!: {message}"), Span::call_site()),
    }
}

/// `answer_keys!()` in the answer key's `lib.rs`: `pub mod labNN;` for every solution
/// `src/labNN.rs` in the tree (every lab's in the course's repository, the released ones in a
/// handout), `KEYS` listing them, and `INSTALL_KEYS`, which puts each key `labNN::LabNN` into a
/// store as its lab's `contracts::labNN::Contract`.
#[proc_macro]
pub fn answer_keys(input: TokenStream) -> TokenStream {
    let labs = match lab_files(input) {
        Ok(labs) => labs,
        Err(message) => {
            return compile_error(&format!("answer_keys!: {message}"), Span::call_site());
        }
    };
    let mut out = String::new();
    let mut numbers = Vec::new();
    let mut installs = Vec::new();
    for lab in &labs {
        out.push_str(&format!("pub mod {lab};"));
        let number = &lab[3..];
        numbers.push(number.trim_start_matches('0').to_string());
        installs.push(format!(
            "|parts: &mut ::contracts::Parts| parts.insert::<::contracts::{lab}::Contract>(::std::sync::Arc::new({lab}::Lab{number}))"
        ));
    }
    out.push_str(&format!(
        "/// The labs whose solution this crate holds: the code of [`pipeline`] that is the \
         answer key. Checks compare a student's function with the key's where it is present \
         (`LabContext::with_key_labs`), and judge by golden cases and properties elsewhere.\n\
         pub const KEYS: &[u32] = &[{}];\
         /// For each lab of [`KEYS`], in order: puts its key into a store.\n\
         const INSTALL_KEYS: [fn(&mut ::contracts::Parts); {}] = [{}];",
        numbers.join(", "),
        installs.len(),
        installs.join(", ")
    ));
    parse(&out)
}
