//! The wire code of a contract: `impl Trait for Remote<dyn Trait>` (the checking side: each
//! method encodes its arguments, has the transport run it on the student's code, decodes the
//! result and writes back what the method may change) and `impl Serve for dyn Trait` (the
//! student's side: decodes a call, runs the method, encodes the result).
//!
//! Each argument is classified by the shape of its type: by value, `&T` (sent), `&mut T` (sent
//! and written back), `&[T]` and `&mut [T]` (as a `Vec<T>`), and closures `&dyn Fn(…) -> R` /
//! `&mut dyn FnMut(…) -> R`, which stay on the checking side and are called back by index. The
//! types themselves only need serde's traits.

use proc_macro::{Delimiter, Span, TokenStream, TokenTree};

use super::{Expansion, split};

/// How an argument (or a closure's argument) crosses the wire.
enum Pass {
    /// By value: sent.
    Value(String),
    /// `&T`: `T` sent; the student's side passes a reference to its copy.
    Ref(String),
    /// `&mut T`: sent, and the value after the call sent back and written over the original.
    Mut(String),
    /// A closure `&dyn Fn(args) -> ret` (`mutable`: `&mut dyn FnMut`): called back.
    Closure {
        mutable: bool,
        args: Vec<Pass>,
        ret: String,
    },
}

impl Pass {
    /// The owned type decoded on the far side (`[T]` becomes `Vec<T>`).
    fn owned(&self) -> &str {
        match self {
            Pass::Value(t) | Pass::Ref(t) | Pass::Mut(t) => t,
            Pass::Closure { .. } => unreachable!("a closure is not decoded"),
        }
    }
}

fn text(tokens: &[TokenTree]) -> String {
    tokens.iter().cloned().collect::<TokenStream>().to_string()
}

/// How a slice type `[E]` travels: the owned type that starts so (and only such a type).
const SLICE_AS_VEC: &str = "::std::vec::Vec<";

/// `T`, or `Vec<E>` for a slice type `[E]`.
fn owned_type(tokens: &[TokenTree]) -> String {
    if let [TokenTree::Group(g)] = tokens
        && g.delimiter() == Delimiter::Bracket
        && !g
            .stream()
            .into_iter()
            .any(|t| matches!(&t, TokenTree::Punct(p) if p.as_char() == ';'))
    {
        return format!("{SLICE_AS_VEC}{}>", g.stream());
    }
    text(tokens)
}

fn is_punct(token: Option<&TokenTree>, c: char) -> bool {
    matches!(token, Some(TokenTree::Punct(p)) if p.as_char() == c)
}

fn is_word(token: Option<&TokenTree>, word: &str) -> bool {
    matches!(token, Some(TokenTree::Ident(i)) if i.to_string() == word)
}

/// The tokens after `->` in `tokens`, as a type (`()` without an arrow).
fn return_type(tokens: &[TokenTree]) -> String {
    let arrow = tokens
        .windows(2)
        .position(|w| is_punct(w.first(), '-') && is_punct(w.get(1), '>'));
    match arrow {
        Some(at) => text(&tokens[at + 2..]),
        None => "()".into(),
    }
}

fn classify(ty: &[TokenTree]) -> Result<Pass, (String, Span)> {
    let span = ty.first().map_or_else(Span::call_site, TokenTree::span);
    if !is_punct(ty.first(), '&') {
        return Ok(Pass::Value(text(ty)));
    }
    if is_punct(ty.get(1), '\'') {
        return Err((
            "a contract's references have no named lifetimes".into(),
            span,
        ));
    }
    let mutable = is_word(ty.get(1), "mut");
    let rest = &ty[1 + usize::from(mutable)..];
    if !is_word(rest.first(), "dyn") {
        return Ok(if mutable {
            Pass::Mut(owned_type(rest))
        } else {
            Pass::Ref(owned_type(rest))
        });
    }
    let closure =
        "a contract's trait objects are closures, `&dyn Fn(…) -> R` or `&mut dyn FnMut(…) -> R`";
    let kind_ok = if mutable {
        is_word(rest.get(1), "FnMut")
    } else {
        is_word(rest.get(1), "Fn")
    };
    let Some(TokenTree::Group(params)) = rest.get(2) else {
        return Err((closure.into(), span));
    };
    if !kind_ok || params.delimiter() != Delimiter::Parenthesis {
        return Err((closure.into(), span));
    }
    let mut args = Vec::new();
    for arg in split(params.stream(), ',') {
        if arg.is_empty() {
            continue;
        }
        match classify(&arg)? {
            Pass::Closure { .. } => {
                return Err(("a closure's arguments are data, not closures".into(), span));
            }
            pass => args.push(pass),
        }
    }
    Ok(Pass::Closure {
        mutable,
        args,
        ret: return_type(&rest[3..]),
    })
}

/// One method of a contract, as the wire sees it.
pub(crate) struct WireMethod {
    pub name: String,
    /// The method as the trait declares it (`fn name(&self, …) -> R`), without attributes.
    pub declaration: Vec<TokenTree>,
    args: Vec<(String, Pass)>,
    ret: String,
}

impl WireMethod {
    /// `params` are the method's parameters after `&self`, each `name: Type`.
    pub fn new(
        name: String,
        declaration: Vec<TokenTree>,
        params: &[Vec<TokenTree>],
    ) -> Result<Self, (String, Span)> {
        let mut args = Vec::new();
        for param in params {
            let [TokenTree::Ident(arg), TokenTree::Punct(_), ty @ ..] = param.as_slice() else {
                continue;
            };
            args.push((arg.to_string(), classify(ty)?));
        }
        let ret = return_type(&declaration[3..]);
        Ok(Self {
            name,
            declaration,
            args,
            ret,
        })
    }
}

/// The encoding of `value` (an expression of the owned type or a reference to it) into the
/// writer `w`.
fn put(w: &str, value: &str) -> String {
    format!("{w}.put(&{value});")
}

/// Writes `decoded` (the owned value the far side sent back) over the `&mut` argument `arg`.
fn write_back(arg: &str, owned: &str, decoded: &str) -> String {
    if owned.starts_with(SLICE_AS_VEC) {
        format!("{arg}.clone_from_slice(&{decoded});")
    } else {
        format!("*{arg} = {decoded};")
    }
}

/// The checking side's closure that answers a call back to the closure argument `arg`.
fn host_callback(index: usize, arg: &str, args: &[Pass], ret: &str) -> String {
    let mut body = String::from("let mut __r = crate::wire::Reader::new(__bytes);");
    let mut call = Vec::new();
    let mut back = String::new();
    for (i, pass) in args.iter().enumerate() {
        let owned = pass.owned();
        body.push_str(&format!("let mut __x{i}: {owned} = __r.take();"));
        match pass {
            Pass::Value(_) => call.push(format!("__x{i}")),
            Pass::Ref(_) => call.push(format!("&__x{i}")),
            Pass::Mut(_) => {
                call.push(format!("&mut __x{i}"));
                back.push_str(&put("__w", &format!("__x{i}")));
            }
            Pass::Closure { .. } => unreachable!(),
        }
    }
    format!(
        "let mut __cb{index} = |__bytes: &[u8]| -> ::std::vec::Vec<u8> {{ {body} \
         let __ret: {ret} = {arg}({call}); let mut __w = crate::wire::Writer::new(); \
         __w.put(&__ret); {back} __w.finish() }};",
        call = call.join(", ")
    )
}

/// The student's side's closure that stands for the closure argument number `index`: it calls
/// back to the checking side.
fn guest_callback(index: usize, args: &[Pass], ret: &str) -> String {
    let mut params = Vec::new();
    let mut send = String::new();
    let mut back = String::new();
    for (i, pass) in args.iter().enumerate() {
        let owned = pass.owned();
        match pass {
            Pass::Value(_) => {
                params.push(format!("__x{i}: {owned}"));
                send.push_str(&put("__w", &format!("__x{i}")));
            }
            Pass::Ref(_) => {
                params.push(format!("__x{i}: &{}", borrowed(owned)));
                send.push_str(&format!("__w.put(__x{i});"));
            }
            Pass::Mut(_) => {
                params.push(format!("__x{i}: &mut {}", borrowed(owned)));
                send.push_str(&format!("__w.put(&*__x{i});"));
                let decoded = "__r.take()".to_string();
                back.push_str(&format!(
                    "{{ let __v: {owned} = {decoded}; {} }}",
                    write_back(&format!("__x{i}"), owned, "__v")
                ));
            }
            Pass::Closure { .. } => unreachable!(),
        }
    }
    format!(
        "move |{params}| -> {ret} {{ let mut __w = crate::wire::Writer::new(); {send} \
         let __b = __host.call_back({index}, __w.finish()); \
         let mut __r = crate::wire::Reader::new(&__b); let __ret: {ret} = __r.take(); {back} __ret }}",
        params = params.join(", ")
    )
}

/// The type a reference argument borrows: `[T]` for an owned `Vec<T>` made from a slice type.
fn borrowed(owned: &str) -> String {
    if let Some(inner) = owned.strip_prefix(SLICE_AS_VEC) {
        return format!("[{}]", inner.strip_suffix('>').unwrap_or(inner));
    }
    owned.to_string()
}

/// `impl Trait for crate::wire::Remote<dyn Trait>` and `impl crate::wire::Serve for dyn Trait`.
pub(crate) fn expand(name: &str, methods: &[WireMethod]) -> Expansion {
    let mut remote = String::new();
    let mut arms = String::new();
    for method in methods {
        let index = &method.name;
        // The checking side.
        let mut body = String::from("let mut __w = crate::wire::Writer::new();");
        let mut callbacks = Vec::new();
        let mut after = String::new();
        // The student's side.
        let mut decode = String::new();
        let mut call = Vec::new();
        let mut reply = String::new();
        let mut closures = 0;
        for (arg, pass) in &method.args {
            match pass {
                Pass::Value(t) => {
                    body.push_str(&put("__w", arg));
                    decode.push_str(&format!("let {arg}: {t} = __a.take();"));
                    call.push(arg.clone());
                }
                Pass::Ref(t) => {
                    body.push_str(&format!("__w.put({arg});"));
                    decode.push_str(&format!("let {arg}: {t} = __a.take();"));
                    call.push(format!("&{arg}"));
                }
                Pass::Mut(t) => {
                    body.push_str(&format!("__w.put(&*{arg});"));
                    after.push_str(&format!(
                        "{{ let __v: {t} = __r.take(); {} }}",
                        write_back(arg, t, "__v")
                    ));
                    decode.push_str(&format!("let mut {arg}: {t} = __a.take();"));
                    call.push(format!("&mut {arg}"));
                    reply.push_str(&put("__o", arg));
                }
                Pass::Closure { mutable, args, ret } => {
                    body.push_str(&host_callback(closures, arg, args, ret));
                    callbacks.push(format!("&mut __cb{closures}"));
                    let closure = guest_callback(closures, args, ret);
                    if *mutable {
                        decode.push_str(&format!("let mut {arg} = {closure};"));
                        call.push(format!("&mut {arg}"));
                    } else {
                        decode.push_str(&format!("let {arg} = {closure};"));
                        call.push(format!("&{arg}"));
                    }
                    closures += 1;
                }
            }
        }
        let ret = &method.ret;
        body.push_str(&format!(
            "let __bytes = self.call({index:?}, __w.finish(), &mut [{}]); \
             let mut __r = crate::wire::Reader::new(&__bytes); let __ret: {ret} = __r.take(); \
             {after} __ret",
            callbacks.join(", ")
        ));
        remote.push_str(&text(&method.declaration));
        remote.push_str(&format!("{{ {body} }}"));
        arms.push_str(&format!(
            "{index:?} => {{ {decode} let __ret: {ret} = self.{}({}); \
             let mut __o = crate::wire::Writer::new(); __o.put(&__ret); {reply} __o.finish() }}",
            method.name,
            call.join(", ")
        ));
    }
    let code = format!(
        "impl<C: ?Sized + {name}> {name} for crate::wire::Remote<C> {{ {remote} }} \
         impl<T: ?Sized + {name}> crate::wire::Serves<dyn {name}> for T {{ \
             #[allow(unused_mut, unused_variables, clippy::let_unit_value)] \
             fn serve_part(&self, __method: &str, __args: &[u8], __host: &dyn crate::wire::Host) \
                 -> ::std::option::Option<::std::vec::Vec<u8>> {{ \
                 let mut __a = crate::wire::Reader::new(__args); \
                 ::std::option::Option::Some(match __method {{ {arms} _ => return ::std::option::Option::None }}) \
             }} \
         }} \
         impl crate::wire::Serve for dyn {name} {{ \
             fn serve(&self, method: &str, args: &[u8], host: &dyn crate::wire::Host) -> ::std::vec::Vec<u8> {{ \
                 crate::wire::Serves::<dyn {name}>::serve_part(self, method, args, host) \
                     .unwrap_or_else(|| crate::wire::unknown_method(method)) \
             }} \
         }}"
    );
    code.parse().map_err(|e| {
        (
            format!("the wire code of {name} does not parse: {e}"),
            Span::call_site(),
        )
    })
}
