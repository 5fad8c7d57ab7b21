// auto-generated: "lalrpop 0.23.2"
// sha3: e18627df3e7b73e9ce4f83610fcded300ae5c0949e64ae2bdf914619d5394963
// features: 
use crate::lexer::{Tok, Lit, LexError};
use crate::ast::{Item, Val};
use lalrpop_util::ErrorRecovery;
#[allow(unused_extern_crates)]
extern crate lalrpop_util as __lalrpop_util;
#[allow(unused_imports)]
use self::__lalrpop_util::state_machine as __state_machine;
#[allow(unused_extern_crates)]
extern crate alloc;

#[rustfmt::skip]
#[allow(explicit_outlives_requirements, non_snake_case, non_camel_case_types, unused_mut, unused_variables, unused_imports, unused_parens, clippy::needless_lifetimes, clippy::type_complexity, clippy::needless_return, clippy::too_many_arguments, clippy::match_single_binding, clippy::clone_on_copy, clippy::unit_arg)]
mod __parse__Items {

    use crate::lexer::{Tok, Lit, LexError};
    use crate::ast::{Item, Val};
    use lalrpop_util::ErrorRecovery;
    #[allow(unused_extern_crates)]
    extern crate lalrpop_util as __lalrpop_util;
    #[allow(unused_imports)]
    use self::__lalrpop_util::state_machine as __state_machine;
    #[allow(unused_extern_crates)]
    extern crate alloc;
    use super::__ToTriple;
    #[allow(dead_code)]
    pub(crate) enum __Symbol<>
     {
        Variant0(Tok),
        Variant1(char),
        Variant2(Lit),
        Variant3(__lalrpop_util::ErrorRecovery<usize, Tok, LexError>),
        Variant4(usize),
        Variant5(Item),
        Variant6(alloc::vec::Vec<Item>),
        Variant7(Vec<Item>),
        Variant8(Val),
    }
    const __ACTION: &[i8] = &[
        // State 0
        9, 10, 11, 0, 3, 5, 4, 6, 16, 12, 14, 13, 15, 17,
        // State 1
        9, 10, 11, 0, 3, 5, 4, 6, 16, 12, 14, 13, 15, 17,
        // State 2
        0, 0, 0, 0, 0, 20, 0, 0, 21, 0, 0, 0, 0, 0,
        // State 3
        0, 0, 0, 0, 0, 20, 0, 0, 21, 0, 0, 0, 0, 0,
        // State 4
        0, 0, 0, 0, 0, 20, 0, 0, 24, 0, 0, 0, 0, 0,
        // State 5
        0, 0, 0, 0, 0, 20, 0, 0, 21, 0, 0, 0, 0, 0,
        // State 6
        -19, -19, -19, 0, -19, -19, -19, -19, -19, -19, -19, -19, -19, -19,
        // State 7
        0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0,
        // State 8
        -3, -3, -3, 0, -3, -3, -3, -3, -3, -3, -3, -3, -3, -3,
        // State 9
        -4, -4, -4, 0, -4, -4, -4, -4, -4, -4, -4, -4, -4, -4,
        // State 10
        -5, -5, -5, 0, -5, -5, -5, -5, -5, -5, -5, -5, -5, -5,
        // State 11
        -7, -7, -7, 0, -7, -7, -7, -7, -7, -7, -7, -7, -7, -7,
        // State 12
        -8, -8, -8, 0, -8, -8, -8, -8, -8, -8, -8, -8, -8, -8,
        // State 13
        -6, -6, -6, 0, -6, -6, -6, -6, -6, -6, -6, -6, -6, -6,
        // State 14
        -9, -9, -9, 0, -9, -9, -9, -9, -9, -9, -9, -9, -9, -9,
        // State 15
        -10, -10, -10, 0, -10, -10, -10, -10, -10, -10, -10, -10, -10, -10,
        // State 16
        -16, -16, -16, 0, -16, -16, -16, -16, -16, -16, -16, -16, -16, -16,
        // State 17
        -20, -20, -20, 0, -20, -20, -20, -20, -20, -20, -20, -20, -20, -20,
        // State 18
        -11, -11, -11, 0, -11, -11, -11, -11, -11, -11, -11, -11, -11, -11,
        // State 19
        0, 0, 0, 0, 0, 0, 0, 0, 26, 0, 0, 0, 0, 0,
        // State 20
        -23, -23, -23, 0, -23, -23, -23, -23, -23, -23, -23, -23, -23, -23,
        // State 21
        -12, -12, -12, 0, -12, -12, -12, -12, -12, -12, -12, -12, -12, -12,
        // State 22
        -14, -14, -14, 0, -14, -14, -14, -14, -14, -14, -14, -14, -14, -14,
        // State 23
        -23, -23, -23, 27, -23, -23, -23, -23, -23, -23, -23, -23, -23, -23,
        // State 24
        -13, -13, -13, 0, -13, -13, -13, -13, -13, -13, -13, -13, -13, -13,
        // State 25
        -24, -24, -24, 0, -24, -24, -24, -24, -24, -24, -24, -24, -24, -24,
        // State 26
        0, 0, 0, 0, 0, 0, 0, 0, 28, 0, 0, 0, 0, 0,
        // State 27
        -15, -15, -15, 0, -15, -15, -15, -15, -15, -15, -15, -15, -15, -15,
    ];
    fn __action(state: i8, integer: usize) -> i8 {
        __ACTION[(state as usize) * 14 + integer]
    }
    const __EOF_ACTION: &[i8] = &[
        // State 0
        -21,
        // State 1
        -22,
        // State 2
        0,
        // State 3
        0,
        // State 4
        0,
        // State 5
        0,
        // State 6
        -19,
        // State 7
        -25,
        // State 8
        -3,
        // State 9
        -4,
        // State 10
        -5,
        // State 11
        -7,
        // State 12
        -8,
        // State 13
        -6,
        // State 14
        -9,
        // State 15
        -10,
        // State 16
        -16,
        // State 17
        -20,
        // State 18
        -11,
        // State 19
        0,
        // State 20
        -23,
        // State 21
        -12,
        // State 22
        -14,
        // State 23
        -23,
        // State 24
        -13,
        // State 25
        -24,
        // State 26
        0,
        // State 27
        -15,
    ];
    fn __goto(state: i8, nt: usize) -> i8 {
        match nt {
            2 => match state {
                1 => 17,
                _ => 6,
            },
            4 => 1,
            5 => 7,
            6 => match state {
                3 => 21,
                4 => 22,
                5 => 24,
                _ => 18,
            },
            _ => 0,
        }
    }
    #[allow(clippy::needless_raw_string_hashes)]
    const __TERMINAL: &[&str] = &[
        r###""%""###,
        r###""*""###,
        r###""/""###,
        r###""=""###,
        r###""N""###,
        r###""R""###,
        r###""O""###,
        r###""addr""###,
        r###""num""###,
        r###""comment""###,
        r###""eob""###,
        r###""cyclehdr""###,
        r###""lexerror""###,
    ];
    fn __expected_tokens(__state: i8) -> alloc::vec::Vec<alloc::string::String> {
        __TERMINAL.iter().enumerate().filter_map(|(index, terminal)| {
            let next_state = __action(__state, index);
            if next_state == 0 {
                None
            } else {
                Some(alloc::string::ToString::to_string(terminal))
            }
        }).collect()
    }
    fn __expected_tokens_from_states<
        'err,
    >(
        __states: &[i8],
        _: core::marker::PhantomData<(&'err ())>,
    ) -> alloc::vec::Vec<alloc::string::String>
    {
        // Emptied by scripts/gen-parsers.sh: partprogram reports no expected tokens.
        alloc::vec::Vec::new()
    }
    struct __StateMachine<'err>
    where 
    {
        errors: &'err mut Vec<ErrorRecovery<usize, Tok, LexError>>,
        __phantom: core::marker::PhantomData<(&'err ())>,
    }
    impl<'err> __state_machine::ParserDefinition for __StateMachine<'err>
    where 
    {
        type Location = usize;
        type Error = LexError;
        type Token = Tok;
        type TokenIndex = usize;
        type Symbol = __Symbol<>;
        type Success = Vec<Item>;
        type StateIndex = i8;
        type Action = i8;
        type ReduceIndex = i8;
        type NonterminalIndex = usize;

        #[inline]
        fn start_location(&self) -> Self::Location {
              Default::default()
        }

        #[inline]
        fn start_state(&self) -> Self::StateIndex {
              0
        }

        #[inline]
        fn token_to_index(&self, token: &Self::Token) -> Option<usize> {
            __token_to_integer(token, core::marker::PhantomData::<(&())>)
        }

        #[inline]
        fn action(&self, state: i8, integer: usize) -> i8 {
            __action(state, integer)
        }

        #[inline]
        fn error_action(&self, state: i8) -> i8 {
            __action(state, 14 - 1)
        }

        #[inline]
        fn eof_action(&self, state: i8) -> i8 {
            __EOF_ACTION[state as usize]
        }

        #[inline]
        fn goto(&self, state: i8, nt: usize) -> i8 {
            __goto(state, nt)
        }

        fn token_to_symbol(&self, token_index: usize, token: Self::Token) -> Self::Symbol {
            __token_to_symbol(token_index, token, core::marker::PhantomData::<(&())>)
        }

        fn expected_tokens(&self, state: i8) -> alloc::vec::Vec<alloc::string::String> {
            __expected_tokens(state)
        }

        fn expected_tokens_from_states(&self, states: &[i8]) -> alloc::vec::Vec<alloc::string::String> {
            __expected_tokens_from_states(states, core::marker::PhantomData::<(&())>)
        }

        #[inline]
        fn uses_error_recovery(&self) -> bool {
            true
        }

        #[inline]
        fn error_recovery_symbol(
            &self,
            recovery: __state_machine::ErrorRecovery<Self>,
        ) -> Self::Symbol {
            __Symbol::Variant3(recovery)
        }

        fn reduce(
            &mut self,
            action: i8,
            start_location: Option<&Self::Location>,
            states: &mut alloc::vec::Vec<i8>,
            symbols: &mut alloc::vec::Vec<__state_machine::SymbolTriple<Self>>,
        ) -> Option<__state_machine::ParseResult<Self>> {
            __reduce(
                self.errors,
                action,
                start_location,
                states,
                symbols,
                core::marker::PhantomData::<(&())>,
            )
        }

        fn simulate_reduce(&self, action: i8) -> __state_machine::SimulatedReduce<Self> {
            __simulate_reduce(action, core::marker::PhantomData::<(&())>)
        }
    }
    fn __token_to_integer<
        'err,
    >(
        __token: &Tok,
        _: core::marker::PhantomData<(&'err ())>,
    ) -> Option<usize>
    {
        #[warn(unused_variables)]
        match __token {
            Tok::Percent if true => Some(0),
            Tok::Star if true => Some(1),
            Tok::Slash if true => Some(2),
            Tok::Eq if true => Some(3),
            Tok::N if true => Some(4),
            Tok::R if true => Some(5),
            Tok::O if true => Some(6),
            Tok::Addr(_) if true => Some(7),
            Tok::Num(_) if true => Some(8),
            Tok::Comment if true => Some(9),
            Tok::Eob if true => Some(10),
            Tok::CycleHeader if true => Some(11),
            Tok::LexError if true => Some(12),
            _ => None,
        }
    }
    fn __token_to_symbol<
        'err,
    >(
        __token_index: usize,
        __token: Tok,
        _: core::marker::PhantomData<(&'err ())>,
    ) -> __Symbol<>
    {
        #[allow(clippy::manual_range_patterns)]match __token_index {
            0 | 1 | 2 | 3 | 4 | 5 | 6 | 9 | 10 | 11 | 12 => __Symbol::Variant0(__token),
            7 => match __token {
                Tok::Addr(__tok0) if true => __Symbol::Variant1(__tok0),
                _ => unreachable!(),
            },
            8 => match __token {
                Tok::Num(__tok0) if true => __Symbol::Variant2(__tok0),
                _ => unreachable!(),
            },
            _ => unreachable!(),
        }
    }
    fn __simulate_reduce<
        'err,
    >(
        __reduce_index: i8,
        _: core::marker::PhantomData<(&'err ())>,
    ) -> __state_machine::SimulatedReduce<__StateMachine<'err>>
    {
        match __reduce_index {
            0 => {
                __state_machine::SimulatedReduce::Reduce {
                    states_to_pop: 0,
                    nonterminal_produced: 0,
                }
            }
            1 => {
                __state_machine::SimulatedReduce::Reduce {
                    states_to_pop: 0,
                    nonterminal_produced: 1,
                }
            }
            2 => {
                __state_machine::SimulatedReduce::Reduce {
                    states_to_pop: 1,
                    nonterminal_produced: 2,
                }
            }
            3 => {
                __state_machine::SimulatedReduce::Reduce {
                    states_to_pop: 1,
                    nonterminal_produced: 2,
                }
            }
            4 => {
                __state_machine::SimulatedReduce::Reduce {
                    states_to_pop: 1,
                    nonterminal_produced: 2,
                }
            }
            5 => {
                __state_machine::SimulatedReduce::Reduce {
                    states_to_pop: 1,
                    nonterminal_produced: 2,
                }
            }
            6 => {
                __state_machine::SimulatedReduce::Reduce {
                    states_to_pop: 1,
                    nonterminal_produced: 2,
                }
            }
            7 => {
                __state_machine::SimulatedReduce::Reduce {
                    states_to_pop: 1,
                    nonterminal_produced: 2,
                }
            }
            8 => {
                __state_machine::SimulatedReduce::Reduce {
                    states_to_pop: 1,
                    nonterminal_produced: 2,
                }
            }
            9 => {
                __state_machine::SimulatedReduce::Reduce {
                    states_to_pop: 1,
                    nonterminal_produced: 2,
                }
            }
            10 => {
                __state_machine::SimulatedReduce::Reduce {
                    states_to_pop: 2,
                    nonterminal_produced: 2,
                }
            }
            11 => {
                __state_machine::SimulatedReduce::Reduce {
                    states_to_pop: 2,
                    nonterminal_produced: 2,
                }
            }
            12 => {
                __state_machine::SimulatedReduce::Reduce {
                    states_to_pop: 2,
                    nonterminal_produced: 2,
                }
            }
            13 => {
                __state_machine::SimulatedReduce::Reduce {
                    states_to_pop: 2,
                    nonterminal_produced: 2,
                }
            }
            14 => {
                __state_machine::SimulatedReduce::Reduce {
                    states_to_pop: 4,
                    nonterminal_produced: 2,
                }
            }
            15 => {
                __state_machine::SimulatedReduce::Reduce {
                    states_to_pop: 1,
                    nonterminal_produced: 2,
                }
            }
            16 => {
                __state_machine::SimulatedReduce::Reduce {
                    states_to_pop: 0,
                    nonterminal_produced: 3,
                }
            }
            17 => {
                __state_machine::SimulatedReduce::Reduce {
                    states_to_pop: 1,
                    nonterminal_produced: 3,
                }
            }
            18 => {
                __state_machine::SimulatedReduce::Reduce {
                    states_to_pop: 1,
                    nonterminal_produced: 4,
                }
            }
            19 => {
                __state_machine::SimulatedReduce::Reduce {
                    states_to_pop: 2,
                    nonterminal_produced: 4,
                }
            }
            20 => {
                __state_machine::SimulatedReduce::Reduce {
                    states_to_pop: 0,
                    nonterminal_produced: 5,
                }
            }
            21 => {
                __state_machine::SimulatedReduce::Reduce {
                    states_to_pop: 1,
                    nonterminal_produced: 5,
                }
            }
            22 => {
                __state_machine::SimulatedReduce::Reduce {
                    states_to_pop: 1,
                    nonterminal_produced: 6,
                }
            }
            23 => {
                __state_machine::SimulatedReduce::Reduce {
                    states_to_pop: 2,
                    nonterminal_produced: 6,
                }
            }
            24 => __state_machine::SimulatedReduce::Accept,
            _ => panic!("invalid reduction index {__reduce_index}")
        }
    }
    pub struct ItemsParser {
        _priv: (),
    }

    impl Default for ItemsParser { fn default() -> Self { Self::new() } }
    impl ItemsParser {
        pub fn new() -> ItemsParser {
            ItemsParser {
                _priv: (),
            }
        }

        #[allow(dead_code)]
        pub fn parse<
            'err,
            __TOKEN: __ToTriple<'err, >,
            __TOKENS: IntoIterator<Item=__TOKEN>,
        >(
            &self,
            errors: &'err mut Vec<ErrorRecovery<usize, Tok, LexError>>,
            __tokens0: __TOKENS,
        ) -> Result<Vec<Item>, __lalrpop_util::ParseError<usize, Tok, LexError>>
        {
            let __tokens = __tokens0.into_iter();
            let mut __tokens = __tokens.map(|t| __ToTriple::to_triple(t));
            __state_machine::Parser::drive(
                __StateMachine {
                    errors,
                    __phantom: core::marker::PhantomData::<(&())>,
                },
                __tokens,
            )
        }
    }
    fn __accepts<
        'err,
    >(
        __error_state: Option<i8>,
        __states: &[i8],
        __opt_integer: Option<usize>,
        _: core::marker::PhantomData<(&'err ())>,
    ) -> bool
    {
        let mut __states = __states.to_vec();
        __states.extend(__error_state);
        loop {
            let mut __states_len = __states.len();
            let __top = __states[__states_len - 1];
            let __action = match __opt_integer {
                None => __EOF_ACTION[__top as usize],
                Some(__integer) => __action(__top, __integer),
            };
            if __action == 0 { return false; }
            if __action > 0 { return true; }
            let (__to_pop, __nt) = match __simulate_reduce(-(__action + 1), core::marker::PhantomData::<(&())>) {
                __state_machine::SimulatedReduce::Reduce {
                    states_to_pop, nonterminal_produced
                } => (states_to_pop, nonterminal_produced),
                __state_machine::SimulatedReduce::Accept => return true,
            };
            __states_len -= __to_pop;
            __states.truncate(__states_len);
            let __top = __states[__states_len - 1];
            let __next_state = __goto(__top, __nt);
            __states.push(__next_state);
        }
    }
    fn __reduce<
        'err,
    >(
        errors: &'err mut Vec<ErrorRecovery<usize, Tok, LexError>>,
        __action: i8,
        __lookahead_start: Option<&usize>,
        __states: &mut alloc::vec::Vec<i8>,
        __symbols: &mut alloc::vec::Vec<(usize,__Symbol<>,usize)>,
        _: core::marker::PhantomData<(&'err ())>,
    ) -> Option<Result<Vec<Item>,__lalrpop_util::ParseError<usize, Tok, LexError>>>
    {
        let (__pop_states, __nonterminal) = match __action {
            0 => {
                __reduce0(errors, __lookahead_start, __symbols, core::marker::PhantomData::<(&())>)
            }
            1 => {
                __reduce1(errors, __lookahead_start, __symbols, core::marker::PhantomData::<(&())>)
            }
            2 => {
                __reduce2(errors, __lookahead_start, __symbols, core::marker::PhantomData::<(&())>)
            }
            3 => {
                __reduce3(errors, __lookahead_start, __symbols, core::marker::PhantomData::<(&())>)
            }
            4 => {
                __reduce4(errors, __lookahead_start, __symbols, core::marker::PhantomData::<(&())>)
            }
            5 => {
                __reduce5(errors, __lookahead_start, __symbols, core::marker::PhantomData::<(&())>)
            }
            6 => {
                __reduce6(errors, __lookahead_start, __symbols, core::marker::PhantomData::<(&())>)
            }
            7 => {
                __reduce7(errors, __lookahead_start, __symbols, core::marker::PhantomData::<(&())>)
            }
            8 => {
                __reduce8(errors, __lookahead_start, __symbols, core::marker::PhantomData::<(&())>)
            }
            9 => {
                __reduce9(errors, __lookahead_start, __symbols, core::marker::PhantomData::<(&())>)
            }
            10 => {
                __reduce10(errors, __lookahead_start, __symbols, core::marker::PhantomData::<(&())>)
            }
            11 => {
                __reduce11(errors, __lookahead_start, __symbols, core::marker::PhantomData::<(&())>)
            }
            12 => {
                __reduce12(errors, __lookahead_start, __symbols, core::marker::PhantomData::<(&())>)
            }
            13 => {
                __reduce13(errors, __lookahead_start, __symbols, core::marker::PhantomData::<(&())>)
            }
            14 => {
                __reduce14(errors, __lookahead_start, __symbols, core::marker::PhantomData::<(&())>)
            }
            15 => {
                __reduce15(errors, __lookahead_start, __symbols, core::marker::PhantomData::<(&())>)
            }
            16 => {
                __reduce16(errors, __lookahead_start, __symbols, core::marker::PhantomData::<(&())>)
            }
            17 => {
                __reduce17(errors, __lookahead_start, __symbols, core::marker::PhantomData::<(&())>)
            }
            18 => {
                __reduce18(errors, __lookahead_start, __symbols, core::marker::PhantomData::<(&())>)
            }
            19 => {
                __reduce19(errors, __lookahead_start, __symbols, core::marker::PhantomData::<(&())>)
            }
            20 => {
                __reduce20(errors, __lookahead_start, __symbols, core::marker::PhantomData::<(&())>)
            }
            21 => {
                __reduce21(errors, __lookahead_start, __symbols, core::marker::PhantomData::<(&())>)
            }
            22 => {
                __reduce22(errors, __lookahead_start, __symbols, core::marker::PhantomData::<(&())>)
            }
            23 => {
                __reduce23(errors, __lookahead_start, __symbols, core::marker::PhantomData::<(&())>)
            }
            24 => {
                // __Items = Items => ActionFn(0);
                let __sym0 = __pop_Variant7(__symbols);
                let __start = __sym0.0.clone();
                let __end = __sym0.2.clone();
                let __nt = super::__action0::<>(errors, __sym0);
                return Some(Ok(__nt));
            }
            _ => panic!("invalid action code {__action}")
        };
        let __states_len = __states.len();
        __states.truncate(__states_len - __pop_states);
        let __state = *__states.last().unwrap();
        let __next_state = __goto(__state, __nonterminal);
        __states.push(__next_state);
        None
    }
    #[inline(never)]
    fn __symbol_type_mismatch() -> ! {
        panic!("symbol type mismatch")
    }
    fn __pop_Variant5<
    >(
        __symbols: &mut alloc::vec::Vec<(usize,__Symbol<>,usize)>
    ) -> (usize, Item, usize)
     {
        match __symbols.pop() {
            Some((__l, __Symbol::Variant5(__v), __r)) => (__l, __v, __r),
            _ => __symbol_type_mismatch()
        }
    }
    fn __pop_Variant2<
    >(
        __symbols: &mut alloc::vec::Vec<(usize,__Symbol<>,usize)>
    ) -> (usize, Lit, usize)
     {
        match __symbols.pop() {
            Some((__l, __Symbol::Variant2(__v), __r)) => (__l, __v, __r),
            _ => __symbol_type_mismatch()
        }
    }
    fn __pop_Variant0<
    >(
        __symbols: &mut alloc::vec::Vec<(usize,__Symbol<>,usize)>
    ) -> (usize, Tok, usize)
     {
        match __symbols.pop() {
            Some((__l, __Symbol::Variant0(__v), __r)) => (__l, __v, __r),
            _ => __symbol_type_mismatch()
        }
    }
    fn __pop_Variant8<
    >(
        __symbols: &mut alloc::vec::Vec<(usize,__Symbol<>,usize)>
    ) -> (usize, Val, usize)
     {
        match __symbols.pop() {
            Some((__l, __Symbol::Variant8(__v), __r)) => (__l, __v, __r),
            _ => __symbol_type_mismatch()
        }
    }
    fn __pop_Variant7<
    >(
        __symbols: &mut alloc::vec::Vec<(usize,__Symbol<>,usize)>
    ) -> (usize, Vec<Item>, usize)
     {
        match __symbols.pop() {
            Some((__l, __Symbol::Variant7(__v), __r)) => (__l, __v, __r),
            _ => __symbol_type_mismatch()
        }
    }
    fn __pop_Variant3<
    >(
        __symbols: &mut alloc::vec::Vec<(usize,__Symbol<>,usize)>
    ) -> (usize, __lalrpop_util::ErrorRecovery<usize, Tok, LexError>, usize)
     {
        match __symbols.pop() {
            Some((__l, __Symbol::Variant3(__v), __r)) => (__l, __v, __r),
            _ => __symbol_type_mismatch()
        }
    }
    fn __pop_Variant6<
    >(
        __symbols: &mut alloc::vec::Vec<(usize,__Symbol<>,usize)>
    ) -> (usize, alloc::vec::Vec<Item>, usize)
     {
        match __symbols.pop() {
            Some((__l, __Symbol::Variant6(__v), __r)) => (__l, __v, __r),
            _ => __symbol_type_mismatch()
        }
    }
    fn __pop_Variant1<
    >(
        __symbols: &mut alloc::vec::Vec<(usize,__Symbol<>,usize)>
    ) -> (usize, char, usize)
     {
        match __symbols.pop() {
            Some((__l, __Symbol::Variant1(__v), __r)) => (__l, __v, __r),
            _ => __symbol_type_mismatch()
        }
    }
    fn __pop_Variant4<
    >(
        __symbols: &mut alloc::vec::Vec<(usize,__Symbol<>,usize)>
    ) -> (usize, usize, usize)
     {
        match __symbols.pop() {
            Some((__l, __Symbol::Variant4(__v), __r)) => (__l, __v, __r),
            _ => __symbol_type_mismatch()
        }
    }
    fn __reduce0<
        'err,
    >(
        errors: &'err mut Vec<ErrorRecovery<usize, Tok, LexError>>,
        __lookahead_start: Option<&usize>,
        __symbols: &mut alloc::vec::Vec<(usize,__Symbol<>,usize)>,
        _: core::marker::PhantomData<(&'err ())>,
    ) -> (usize, usize)
    {
        // @L =  => ActionFn(19);
        let __start = __lookahead_start.cloned().or_else(|| __symbols.last().map(|s| s.2.clone())).unwrap_or_default();
        let __end = __start.clone();
        let __nt = super::__action19::<>(errors, &__start, &__end);
        __symbols.push((__start, __Symbol::Variant4(__nt), __end));
        (0, 0)
    }
    fn __reduce1<
        'err,
    >(
        errors: &'err mut Vec<ErrorRecovery<usize, Tok, LexError>>,
        __lookahead_start: Option<&usize>,
        __symbols: &mut alloc::vec::Vec<(usize,__Symbol<>,usize)>,
        _: core::marker::PhantomData<(&'err ())>,
    ) -> (usize, usize)
    {
        // @R =  => ActionFn(18);
        let __start = __lookahead_start.cloned().or_else(|| __symbols.last().map(|s| s.2.clone())).unwrap_or_default();
        let __end = __start.clone();
        let __nt = super::__action18::<>(errors, &__start, &__end);
        __symbols.push((__start, __Symbol::Variant4(__nt), __end));
        (0, 1)
    }
    fn __reduce2<
        'err,
    >(
        errors: &'err mut Vec<ErrorRecovery<usize, Tok, LexError>>,
        __lookahead_start: Option<&usize>,
        __symbols: &mut alloc::vec::Vec<(usize,__Symbol<>,usize)>,
        _: core::marker::PhantomData<(&'err ())>,
    ) -> (usize, usize)
    {
        // Item = "%" => ActionFn(38);
        let __sym0 = __pop_Variant0(__symbols);
        let __start = __sym0.0.clone();
        let __end = __sym0.2.clone();
        let __nt = super::__action38::<>(errors, __sym0);
        __symbols.push((__start, __Symbol::Variant5(__nt), __end));
        (1, 2)
    }
    fn __reduce3<
        'err,
    >(
        errors: &'err mut Vec<ErrorRecovery<usize, Tok, LexError>>,
        __lookahead_start: Option<&usize>,
        __symbols: &mut alloc::vec::Vec<(usize,__Symbol<>,usize)>,
        _: core::marker::PhantomData<(&'err ())>,
    ) -> (usize, usize)
    {
        // Item = "*" => ActionFn(39);
        let __sym0 = __pop_Variant0(__symbols);
        let __start = __sym0.0.clone();
        let __end = __sym0.2.clone();
        let __nt = super::__action39::<>(errors, __sym0);
        __symbols.push((__start, __Symbol::Variant5(__nt), __end));
        (1, 2)
    }
    fn __reduce4<
        'err,
    >(
        errors: &'err mut Vec<ErrorRecovery<usize, Tok, LexError>>,
        __lookahead_start: Option<&usize>,
        __symbols: &mut alloc::vec::Vec<(usize,__Symbol<>,usize)>,
        _: core::marker::PhantomData<(&'err ())>,
    ) -> (usize, usize)
    {
        // Item = "/" => ActionFn(40);
        let __sym0 = __pop_Variant0(__symbols);
        let __start = __sym0.0.clone();
        let __end = __sym0.2.clone();
        let __nt = super::__action40::<>(errors, __sym0);
        __symbols.push((__start, __Symbol::Variant5(__nt), __end));
        (1, 2)
    }
    fn __reduce5<
        'err,
    >(
        errors: &'err mut Vec<ErrorRecovery<usize, Tok, LexError>>,
        __lookahead_start: Option<&usize>,
        __symbols: &mut alloc::vec::Vec<(usize,__Symbol<>,usize)>,
        _: core::marker::PhantomData<(&'err ())>,
    ) -> (usize, usize)
    {
        // Item = "eob" => ActionFn(41);
        let __sym0 = __pop_Variant0(__symbols);
        let __start = __sym0.0.clone();
        let __end = __sym0.2.clone();
        let __nt = super::__action41::<>(errors, __sym0);
        __symbols.push((__start, __Symbol::Variant5(__nt), __end));
        (1, 2)
    }
    fn __reduce6<
        'err,
    >(
        errors: &'err mut Vec<ErrorRecovery<usize, Tok, LexError>>,
        __lookahead_start: Option<&usize>,
        __symbols: &mut alloc::vec::Vec<(usize,__Symbol<>,usize)>,
        _: core::marker::PhantomData<(&'err ())>,
    ) -> (usize, usize)
    {
        // Item = "comment" => ActionFn(42);
        let __sym0 = __pop_Variant0(__symbols);
        let __start = __sym0.0.clone();
        let __end = __sym0.2.clone();
        let __nt = super::__action42::<>(errors, __sym0);
        __symbols.push((__start, __Symbol::Variant5(__nt), __end));
        (1, 2)
    }
    fn __reduce7<
        'err,
    >(
        errors: &'err mut Vec<ErrorRecovery<usize, Tok, LexError>>,
        __lookahead_start: Option<&usize>,
        __symbols: &mut alloc::vec::Vec<(usize,__Symbol<>,usize)>,
        _: core::marker::PhantomData<(&'err ())>,
    ) -> (usize, usize)
    {
        // Item = "cyclehdr" => ActionFn(43);
        let __sym0 = __pop_Variant0(__symbols);
        let __start = __sym0.0.clone();
        let __end = __sym0.2.clone();
        let __nt = super::__action43::<>(errors, __sym0);
        __symbols.push((__start, __Symbol::Variant5(__nt), __end));
        (1, 2)
    }
    fn __reduce8<
        'err,
    >(
        errors: &'err mut Vec<ErrorRecovery<usize, Tok, LexError>>,
        __lookahead_start: Option<&usize>,
        __symbols: &mut alloc::vec::Vec<(usize,__Symbol<>,usize)>,
        _: core::marker::PhantomData<(&'err ())>,
    ) -> (usize, usize)
    {
        // Item = "lexerror" => ActionFn(44);
        let __sym0 = __pop_Variant0(__symbols);
        let __start = __sym0.0.clone();
        let __end = __sym0.2.clone();
        let __nt = super::__action44::<>(errors, __sym0);
        __symbols.push((__start, __Symbol::Variant5(__nt), __end));
        (1, 2)
    }
    fn __reduce9<
        'err,
    >(
        errors: &'err mut Vec<ErrorRecovery<usize, Tok, LexError>>,
        __lookahead_start: Option<&usize>,
        __symbols: &mut alloc::vec::Vec<(usize,__Symbol<>,usize)>,
        _: core::marker::PhantomData<(&'err ())>,
    ) -> (usize, usize)
    {
        // Item = "num" => ActionFn(45);
        let __sym0 = __pop_Variant2(__symbols);
        let __start = __sym0.0.clone();
        let __end = __sym0.2.clone();
        let __nt = super::__action45::<>(errors, __sym0);
        __symbols.push((__start, __Symbol::Variant5(__nt), __end));
        (1, 2)
    }
    fn __reduce10<
        'err,
    >(
        errors: &'err mut Vec<ErrorRecovery<usize, Tok, LexError>>,
        __lookahead_start: Option<&usize>,
        __symbols: &mut alloc::vec::Vec<(usize,__Symbol<>,usize)>,
        _: core::marker::PhantomData<(&'err ())>,
    ) -> (usize, usize)
    {
        // Item = "N", Value => ActionFn(46);
        assert!(__symbols.len() >= 2);
        let __sym1 = __pop_Variant8(__symbols);
        let __sym0 = __pop_Variant0(__symbols);
        let __start = __sym0.0.clone();
        let __end = __sym1.2.clone();
        let __nt = super::__action46::<>(errors, __sym0, __sym1);
        __symbols.push((__start, __Symbol::Variant5(__nt), __end));
        (2, 2)
    }
    fn __reduce11<
        'err,
    >(
        errors: &'err mut Vec<ErrorRecovery<usize, Tok, LexError>>,
        __lookahead_start: Option<&usize>,
        __symbols: &mut alloc::vec::Vec<(usize,__Symbol<>,usize)>,
        _: core::marker::PhantomData<(&'err ())>,
    ) -> (usize, usize)
    {
        // Item = "O", Value => ActionFn(47);
        assert!(__symbols.len() >= 2);
        let __sym1 = __pop_Variant8(__symbols);
        let __sym0 = __pop_Variant0(__symbols);
        let __start = __sym0.0.clone();
        let __end = __sym1.2.clone();
        let __nt = super::__action47::<>(errors, __sym0, __sym1);
        __symbols.push((__start, __Symbol::Variant5(__nt), __end));
        (2, 2)
    }
    fn __reduce12<
        'err,
    >(
        errors: &'err mut Vec<ErrorRecovery<usize, Tok, LexError>>,
        __lookahead_start: Option<&usize>,
        __symbols: &mut alloc::vec::Vec<(usize,__Symbol<>,usize)>,
        _: core::marker::PhantomData<(&'err ())>,
    ) -> (usize, usize)
    {
        // Item = "addr", Value => ActionFn(48);
        assert!(__symbols.len() >= 2);
        let __sym1 = __pop_Variant8(__symbols);
        let __sym0 = __pop_Variant1(__symbols);
        let __start = __sym0.0.clone();
        let __end = __sym1.2.clone();
        let __nt = super::__action48::<>(errors, __sym0, __sym1);
        __symbols.push((__start, __Symbol::Variant5(__nt), __end));
        (2, 2)
    }
    fn __reduce13<
        'err,
    >(
        errors: &'err mut Vec<ErrorRecovery<usize, Tok, LexError>>,
        __lookahead_start: Option<&usize>,
        __symbols: &mut alloc::vec::Vec<(usize,__Symbol<>,usize)>,
        _: core::marker::PhantomData<(&'err ())>,
    ) -> (usize, usize)
    {
        // Item = "R", Value => ActionFn(49);
        assert!(__symbols.len() >= 2);
        let __sym1 = __pop_Variant8(__symbols);
        let __sym0 = __pop_Variant0(__symbols);
        let __start = __sym0.0.clone();
        let __end = __sym1.2.clone();
        let __nt = super::__action49::<>(errors, __sym0, __sym1);
        __symbols.push((__start, __Symbol::Variant5(__nt), __end));
        (2, 2)
    }
    fn __reduce14<
        'err,
    >(
        errors: &'err mut Vec<ErrorRecovery<usize, Tok, LexError>>,
        __lookahead_start: Option<&usize>,
        __symbols: &mut alloc::vec::Vec<(usize,__Symbol<>,usize)>,
        _: core::marker::PhantomData<(&'err ())>,
    ) -> (usize, usize)
    {
        // Item = "R", "num", "=", "num" => ActionFn(50);
        assert!(__symbols.len() >= 4);
        let __sym3 = __pop_Variant2(__symbols);
        let __sym2 = __pop_Variant0(__symbols);
        let __sym1 = __pop_Variant2(__symbols);
        let __sym0 = __pop_Variant0(__symbols);
        let __start = __sym0.0.clone();
        let __end = __sym3.2.clone();
        let __nt = super::__action50::<>(errors, __sym0, __sym1, __sym2, __sym3);
        __symbols.push((__start, __Symbol::Variant5(__nt), __end));
        (4, 2)
    }
    fn __reduce15<
        'err,
    >(
        errors: &'err mut Vec<ErrorRecovery<usize, Tok, LexError>>,
        __lookahead_start: Option<&usize>,
        __symbols: &mut alloc::vec::Vec<(usize,__Symbol<>,usize)>,
        _: core::marker::PhantomData<(&'err ())>,
    ) -> (usize, usize)
    {
        // Item = error => ActionFn(51);
        let __sym0 = __pop_Variant3(__symbols);
        let __start = __sym0.0.clone();
        let __end = __sym0.2.clone();
        let __nt = super::__action51::<>(errors, __sym0);
        __symbols.push((__start, __Symbol::Variant5(__nt), __end));
        (1, 2)
    }
    fn __reduce16<
        'err,
    >(
        errors: &'err mut Vec<ErrorRecovery<usize, Tok, LexError>>,
        __lookahead_start: Option<&usize>,
        __symbols: &mut alloc::vec::Vec<(usize,__Symbol<>,usize)>,
        _: core::marker::PhantomData<(&'err ())>,
    ) -> (usize, usize)
    {
        // Item* =  => ActionFn(20);
        let __start = __lookahead_start.cloned().or_else(|| __symbols.last().map(|s| s.2.clone())).unwrap_or_default();
        let __end = __start.clone();
        let __nt = super::__action20::<>(errors, &__start, &__end);
        __symbols.push((__start, __Symbol::Variant6(__nt), __end));
        (0, 3)
    }
    fn __reduce17<
        'err,
    >(
        errors: &'err mut Vec<ErrorRecovery<usize, Tok, LexError>>,
        __lookahead_start: Option<&usize>,
        __symbols: &mut alloc::vec::Vec<(usize,__Symbol<>,usize)>,
        _: core::marker::PhantomData<(&'err ())>,
    ) -> (usize, usize)
    {
        // Item* = Item+ => ActionFn(21);
        let __sym0 = __pop_Variant6(__symbols);
        let __start = __sym0.0.clone();
        let __end = __sym0.2.clone();
        let __nt = super::__action21::<>(errors, __sym0);
        __symbols.push((__start, __Symbol::Variant6(__nt), __end));
        (1, 3)
    }
    fn __reduce18<
        'err,
    >(
        errors: &'err mut Vec<ErrorRecovery<usize, Tok, LexError>>,
        __lookahead_start: Option<&usize>,
        __symbols: &mut alloc::vec::Vec<(usize,__Symbol<>,usize)>,
        _: core::marker::PhantomData<(&'err ())>,
    ) -> (usize, usize)
    {
        // Item+ = Item => ActionFn(22);
        let __sym0 = __pop_Variant5(__symbols);
        let __start = __sym0.0.clone();
        let __end = __sym0.2.clone();
        let __nt = super::__action22::<>(errors, __sym0);
        __symbols.push((__start, __Symbol::Variant6(__nt), __end));
        (1, 4)
    }
    fn __reduce19<
        'err,
    >(
        errors: &'err mut Vec<ErrorRecovery<usize, Tok, LexError>>,
        __lookahead_start: Option<&usize>,
        __symbols: &mut alloc::vec::Vec<(usize,__Symbol<>,usize)>,
        _: core::marker::PhantomData<(&'err ())>,
    ) -> (usize, usize)
    {
        // Item+ = Item+, Item => ActionFn(23);
        assert!(__symbols.len() >= 2);
        let __sym1 = __pop_Variant5(__symbols);
        let __sym0 = __pop_Variant6(__symbols);
        let __start = __sym0.0.clone();
        let __end = __sym1.2.clone();
        let __nt = super::__action23::<>(errors, __sym0, __sym1);
        __symbols.push((__start, __Symbol::Variant6(__nt), __end));
        (2, 4)
    }
    fn __reduce20<
        'err,
    >(
        errors: &'err mut Vec<ErrorRecovery<usize, Tok, LexError>>,
        __lookahead_start: Option<&usize>,
        __symbols: &mut alloc::vec::Vec<(usize,__Symbol<>,usize)>,
        _: core::marker::PhantomData<(&'err ())>,
    ) -> (usize, usize)
    {
        // Items =  => ActionFn(52);
        let __start = __lookahead_start.cloned().or_else(|| __symbols.last().map(|s| s.2.clone())).unwrap_or_default();
        let __end = __start.clone();
        let __nt = super::__action52::<>(errors, &__start, &__end);
        __symbols.push((__start, __Symbol::Variant7(__nt), __end));
        (0, 5)
    }
    fn __reduce21<
        'err,
    >(
        errors: &'err mut Vec<ErrorRecovery<usize, Tok, LexError>>,
        __lookahead_start: Option<&usize>,
        __symbols: &mut alloc::vec::Vec<(usize,__Symbol<>,usize)>,
        _: core::marker::PhantomData<(&'err ())>,
    ) -> (usize, usize)
    {
        // Items = Item+ => ActionFn(53);
        let __sym0 = __pop_Variant6(__symbols);
        let __start = __sym0.0.clone();
        let __end = __sym0.2.clone();
        let __nt = super::__action53::<>(errors, __sym0);
        __symbols.push((__start, __Symbol::Variant7(__nt), __end));
        (1, 5)
    }
    fn __reduce22<
        'err,
    >(
        errors: &'err mut Vec<ErrorRecovery<usize, Tok, LexError>>,
        __lookahead_start: Option<&usize>,
        __symbols: &mut alloc::vec::Vec<(usize,__Symbol<>,usize)>,
        _: core::marker::PhantomData<(&'err ())>,
    ) -> (usize, usize)
    {
        // Value = "num" => ActionFn(2);
        let __sym0 = __pop_Variant2(__symbols);
        let __start = __sym0.0.clone();
        let __end = __sym0.2.clone();
        let __nt = super::__action2::<>(errors, __sym0);
        __symbols.push((__start, __Symbol::Variant8(__nt), __end));
        (1, 6)
    }
    fn __reduce23<
        'err,
    >(
        errors: &'err mut Vec<ErrorRecovery<usize, Tok, LexError>>,
        __lookahead_start: Option<&usize>,
        __symbols: &mut alloc::vec::Vec<(usize,__Symbol<>,usize)>,
        _: core::marker::PhantomData<(&'err ())>,
    ) -> (usize, usize)
    {
        // Value = "R", "num" => ActionFn(3);
        assert!(__symbols.len() >= 2);
        let __sym1 = __pop_Variant2(__symbols);
        let __sym0 = __pop_Variant0(__symbols);
        let __start = __sym0.0.clone();
        let __end = __sym1.2.clone();
        let __nt = super::__action3::<>(errors, __sym0, __sym1);
        __symbols.push((__start, __Symbol::Variant8(__nt), __end));
        (2, 6)
    }
}
#[allow(unused_imports)]
pub use self::__parse__Items::ItemsParser;

#[allow(unused_variables)]
#[allow(clippy::too_many_arguments, clippy::needless_lifetimes, clippy::just_underscores_and_digits, clippy::extra_unused_type_parameters)]
fn __action0<
    'err,
>(
    errors: &'err mut Vec<ErrorRecovery<usize, Tok, LexError>>,
    (_, __0, _): (usize, Vec<Item>, usize),
) -> Vec<Item>
{
    __0
}

#[allow(unused_variables)]
#[allow(clippy::too_many_arguments, clippy::needless_lifetimes, clippy::just_underscores_and_digits, clippy::extra_unused_type_parameters)]
fn __action1<
    'err,
>(
    errors: &'err mut Vec<ErrorRecovery<usize, Tok, LexError>>,
    (_, __0, _): (usize, alloc::vec::Vec<Item>, usize),
) -> Vec<Item>
{
    __0
}

#[allow(unused_variables)]
#[allow(clippy::too_many_arguments, clippy::needless_lifetimes, clippy::just_underscores_and_digits, clippy::extra_unused_type_parameters)]
fn __action2<
    'err,
>(
    errors: &'err mut Vec<ErrorRecovery<usize, Tok, LexError>>,
    (_, n, _): (usize, Lit, usize),
) -> Val
{
    Val::Lit(n)
}

#[allow(unused_variables)]
#[allow(clippy::too_many_arguments, clippy::needless_lifetimes, clippy::just_underscores_and_digits, clippy::extra_unused_type_parameters)]
fn __action3<
    'err,
>(
    errors: &'err mut Vec<ErrorRecovery<usize, Tok, LexError>>,
    (_, _, _): (usize, Tok, usize),
    (_, n, _): (usize, Lit, usize),
) -> Val
{
    Val::Param(n)
}

#[allow(unused_variables)]
#[allow(clippy::too_many_arguments, clippy::needless_lifetimes, clippy::just_underscores_and_digits, clippy::extra_unused_type_parameters)]
fn __action4<
    'err,
>(
    errors: &'err mut Vec<ErrorRecovery<usize, Tok, LexError>>,
    (_, l, _): (usize, usize, usize),
    (_, _, _): (usize, Tok, usize),
    (_, r, _): (usize, usize, usize),
) -> Item
{
    Item::Percent(l..r)
}

#[allow(unused_variables)]
#[allow(clippy::too_many_arguments, clippy::needless_lifetimes, clippy::just_underscores_and_digits, clippy::extra_unused_type_parameters)]
fn __action5<
    'err,
>(
    errors: &'err mut Vec<ErrorRecovery<usize, Tok, LexError>>,
    (_, l, _): (usize, usize, usize),
    (_, _, _): (usize, Tok, usize),
    (_, r, _): (usize, usize, usize),
) -> Item
{
    Item::Star(l..r)
}

#[allow(unused_variables)]
#[allow(clippy::too_many_arguments, clippy::needless_lifetimes, clippy::just_underscores_and_digits, clippy::extra_unused_type_parameters)]
fn __action6<
    'err,
>(
    errors: &'err mut Vec<ErrorRecovery<usize, Tok, LexError>>,
    (_, l, _): (usize, usize, usize),
    (_, _, _): (usize, Tok, usize),
    (_, r, _): (usize, usize, usize),
) -> Item
{
    Item::Slash(l..r)
}

#[allow(unused_variables)]
#[allow(clippy::too_many_arguments, clippy::needless_lifetimes, clippy::just_underscores_and_digits, clippy::extra_unused_type_parameters)]
fn __action7<
    'err,
>(
    errors: &'err mut Vec<ErrorRecovery<usize, Tok, LexError>>,
    (_, l, _): (usize, usize, usize),
    (_, _, _): (usize, Tok, usize),
    (_, r, _): (usize, usize, usize),
) -> Item
{
    Item::Eob(l..r)
}

#[allow(unused_variables)]
#[allow(clippy::too_many_arguments, clippy::needless_lifetimes, clippy::just_underscores_and_digits, clippy::extra_unused_type_parameters)]
fn __action8<
    'err,
>(
    errors: &'err mut Vec<ErrorRecovery<usize, Tok, LexError>>,
    (_, l, _): (usize, usize, usize),
    (_, _, _): (usize, Tok, usize),
    (_, r, _): (usize, usize, usize),
) -> Item
{
    Item::Comment(l..r)
}

#[allow(unused_variables)]
#[allow(clippy::too_many_arguments, clippy::needless_lifetimes, clippy::just_underscores_and_digits, clippy::extra_unused_type_parameters)]
fn __action9<
    'err,
>(
    errors: &'err mut Vec<ErrorRecovery<usize, Tok, LexError>>,
    (_, l, _): (usize, usize, usize),
    (_, _, _): (usize, Tok, usize),
    (_, r, _): (usize, usize, usize),
) -> Item
{
    Item::CycleHeader(l..r)
}

#[allow(unused_variables)]
#[allow(clippy::too_many_arguments, clippy::needless_lifetimes, clippy::just_underscores_and_digits, clippy::extra_unused_type_parameters)]
fn __action10<
    'err,
>(
    errors: &'err mut Vec<ErrorRecovery<usize, Tok, LexError>>,
    (_, l, _): (usize, usize, usize),
    (_, _, _): (usize, Tok, usize),
    (_, r, _): (usize, usize, usize),
) -> Item
{
    Item::Error(l..r)
}

#[allow(unused_variables)]
#[allow(clippy::too_many_arguments, clippy::needless_lifetimes, clippy::just_underscores_and_digits, clippy::extra_unused_type_parameters)]
fn __action11<
    'err,
>(
    errors: &'err mut Vec<ErrorRecovery<usize, Tok, LexError>>,
    (_, l, _): (usize, usize, usize),
    (_, _, _): (usize, Lit, usize),
    (_, r, _): (usize, usize, usize),
) -> Item
{
    Item::Orphan(l..r)
}

#[allow(unused_variables)]
#[allow(clippy::too_many_arguments, clippy::needless_lifetimes, clippy::just_underscores_and_digits, clippy::extra_unused_type_parameters)]
fn __action12<
    'err,
>(
    errors: &'err mut Vec<ErrorRecovery<usize, Tok, LexError>>,
    (_, l, _): (usize, usize, usize),
    (_, _, _): (usize, Tok, usize),
    (_, v, _): (usize, Val, usize),
    (_, r, _): (usize, usize, usize),
) -> Item
{
    Item::Word('N', v, l..r)
}

#[allow(unused_variables)]
#[allow(clippy::too_many_arguments, clippy::needless_lifetimes, clippy::just_underscores_and_digits, clippy::extra_unused_type_parameters)]
fn __action13<
    'err,
>(
    errors: &'err mut Vec<ErrorRecovery<usize, Tok, LexError>>,
    (_, l, _): (usize, usize, usize),
    (_, _, _): (usize, Tok, usize),
    (_, v, _): (usize, Val, usize),
    (_, r, _): (usize, usize, usize),
) -> Item
{
    Item::Word('O', v, l..r)
}

#[allow(unused_variables)]
#[allow(clippy::too_many_arguments, clippy::needless_lifetimes, clippy::just_underscores_and_digits, clippy::extra_unused_type_parameters)]
fn __action14<
    'err,
>(
    errors: &'err mut Vec<ErrorRecovery<usize, Tok, LexError>>,
    (_, l, _): (usize, usize, usize),
    (_, a, _): (usize, char, usize),
    (_, v, _): (usize, Val, usize),
    (_, r, _): (usize, usize, usize),
) -> Item
{
    Item::Word(a, v, l..r)
}

#[allow(unused_variables)]
#[allow(clippy::too_many_arguments, clippy::needless_lifetimes, clippy::just_underscores_and_digits, clippy::extra_unused_type_parameters)]
fn __action15<
    'err,
>(
    errors: &'err mut Vec<ErrorRecovery<usize, Tok, LexError>>,
    (_, l, _): (usize, usize, usize),
    (_, _, _): (usize, Tok, usize),
    (_, v, _): (usize, Val, usize),
    (_, r, _): (usize, usize, usize),
) -> Item
{
    Item::Word('R', v, l..r)
}

#[allow(unused_variables)]
#[allow(clippy::too_many_arguments, clippy::needless_lifetimes, clippy::just_underscores_and_digits, clippy::extra_unused_type_parameters)]
fn __action16<
    'err,
>(
    errors: &'err mut Vec<ErrorRecovery<usize, Tok, LexError>>,
    (_, l, _): (usize, usize, usize),
    (_, _, _): (usize, Tok, usize),
    (_, p, _): (usize, Lit, usize),
    (_, _, _): (usize, Tok, usize),
    (_, v, _): (usize, Lit, usize),
    (_, r, _): (usize, usize, usize),
) -> Item
{
    Item::Decl(p, v, l..r)
}

#[allow(unused_variables)]
#[allow(clippy::too_many_arguments, clippy::needless_lifetimes, clippy::just_underscores_and_digits, clippy::extra_unused_type_parameters)]
fn __action17<
    'err,
>(
    errors: &'err mut Vec<ErrorRecovery<usize, Tok, LexError>>,
    (_, l, _): (usize, usize, usize),
    (_, e, _): (usize, __lalrpop_util::ErrorRecovery<usize, Tok, LexError>, usize),
    (_, r, _): (usize, usize, usize),
) -> Item
{
    { errors.push(e); Item::Error(l..r) }
}

#[allow(unused_variables)]
#[allow(clippy::needless_lifetimes)]
fn __action18<
    'err,
>(
    errors: &'err mut Vec<ErrorRecovery<usize, Tok, LexError>>,
    __lookbehind: &usize,
    __lookahead: &usize,
) -> usize
{
    *__lookbehind
}

#[allow(unused_variables)]
#[allow(clippy::needless_lifetimes)]
fn __action19<
    'err,
>(
    errors: &'err mut Vec<ErrorRecovery<usize, Tok, LexError>>,
    __lookbehind: &usize,
    __lookahead: &usize,
) -> usize
{
    *__lookahead
}

#[allow(unused_variables)]
#[allow(clippy::too_many_arguments, clippy::needless_lifetimes, clippy::just_underscores_and_digits, clippy::extra_unused_type_parameters)]
fn __action20<
    'err,
>(
    errors: &'err mut Vec<ErrorRecovery<usize, Tok, LexError>>,
    __lookbehind: &usize,
    __lookahead: &usize,
) -> alloc::vec::Vec<Item>
{
    alloc::vec![]
}

#[allow(unused_variables)]
#[allow(clippy::too_many_arguments, clippy::needless_lifetimes, clippy::just_underscores_and_digits, clippy::extra_unused_type_parameters)]
fn __action21<
    'err,
>(
    errors: &'err mut Vec<ErrorRecovery<usize, Tok, LexError>>,
    (_, v, _): (usize, alloc::vec::Vec<Item>, usize),
) -> alloc::vec::Vec<Item>
{
    v
}

#[allow(unused_variables)]
#[allow(clippy::too_many_arguments, clippy::needless_lifetimes, clippy::just_underscores_and_digits, clippy::extra_unused_type_parameters)]
fn __action22<
    'err,
>(
    errors: &'err mut Vec<ErrorRecovery<usize, Tok, LexError>>,
    (_, __0, _): (usize, Item, usize),
) -> alloc::vec::Vec<Item>
{
    alloc::vec![__0]
}

#[allow(unused_variables)]
#[allow(clippy::too_many_arguments, clippy::needless_lifetimes, clippy::just_underscores_and_digits, clippy::extra_unused_type_parameters)]
fn __action23<
    'err,
>(
    errors: &'err mut Vec<ErrorRecovery<usize, Tok, LexError>>,
    (_, v, _): (usize, alloc::vec::Vec<Item>, usize),
    (_, e, _): (usize, Item, usize),
) -> alloc::vec::Vec<Item>
{
    { let mut v = v; v.push(e); v }
}

#[allow(unused_variables)]
#[allow(clippy::too_many_arguments, clippy::needless_lifetimes,
    clippy::just_underscores_and_digits, clippy::clone_on_copy, clippy::unit_arg)]
fn __action24<
    'err,
>(
    errors: &'err mut Vec<ErrorRecovery<usize, Tok, LexError>>,
    __0: (usize, Tok, usize),
    __1: (usize, usize, usize),
) -> Item
{
    let __start0 = __0.0.clone();
    let __end0 = __0.0.clone();
    let __temp0 = __action19(
        errors,
        &__start0,
        &__end0,
    );
    let __temp0 = (__start0, __temp0, __end0);
    __action4(
        errors,
        __temp0,
        __0,
        __1,
    )
}

#[allow(unused_variables)]
#[allow(clippy::too_many_arguments, clippy::needless_lifetimes,
    clippy::just_underscores_and_digits, clippy::clone_on_copy, clippy::unit_arg)]
fn __action25<
    'err,
>(
    errors: &'err mut Vec<ErrorRecovery<usize, Tok, LexError>>,
    __0: (usize, Tok, usize),
    __1: (usize, usize, usize),
) -> Item
{
    let __start0 = __0.0.clone();
    let __end0 = __0.0.clone();
    let __temp0 = __action19(
        errors,
        &__start0,
        &__end0,
    );
    let __temp0 = (__start0, __temp0, __end0);
    __action5(
        errors,
        __temp0,
        __0,
        __1,
    )
}

#[allow(unused_variables)]
#[allow(clippy::too_many_arguments, clippy::needless_lifetimes,
    clippy::just_underscores_and_digits, clippy::clone_on_copy, clippy::unit_arg)]
fn __action26<
    'err,
>(
    errors: &'err mut Vec<ErrorRecovery<usize, Tok, LexError>>,
    __0: (usize, Tok, usize),
    __1: (usize, usize, usize),
) -> Item
{
    let __start0 = __0.0.clone();
    let __end0 = __0.0.clone();
    let __temp0 = __action19(
        errors,
        &__start0,
        &__end0,
    );
    let __temp0 = (__start0, __temp0, __end0);
    __action6(
        errors,
        __temp0,
        __0,
        __1,
    )
}

#[allow(unused_variables)]
#[allow(clippy::too_many_arguments, clippy::needless_lifetimes,
    clippy::just_underscores_and_digits, clippy::clone_on_copy, clippy::unit_arg)]
fn __action27<
    'err,
>(
    errors: &'err mut Vec<ErrorRecovery<usize, Tok, LexError>>,
    __0: (usize, Tok, usize),
    __1: (usize, usize, usize),
) -> Item
{
    let __start0 = __0.0.clone();
    let __end0 = __0.0.clone();
    let __temp0 = __action19(
        errors,
        &__start0,
        &__end0,
    );
    let __temp0 = (__start0, __temp0, __end0);
    __action7(
        errors,
        __temp0,
        __0,
        __1,
    )
}

#[allow(unused_variables)]
#[allow(clippy::too_many_arguments, clippy::needless_lifetimes,
    clippy::just_underscores_and_digits, clippy::clone_on_copy, clippy::unit_arg)]
fn __action28<
    'err,
>(
    errors: &'err mut Vec<ErrorRecovery<usize, Tok, LexError>>,
    __0: (usize, Tok, usize),
    __1: (usize, usize, usize),
) -> Item
{
    let __start0 = __0.0.clone();
    let __end0 = __0.0.clone();
    let __temp0 = __action19(
        errors,
        &__start0,
        &__end0,
    );
    let __temp0 = (__start0, __temp0, __end0);
    __action8(
        errors,
        __temp0,
        __0,
        __1,
    )
}

#[allow(unused_variables)]
#[allow(clippy::too_many_arguments, clippy::needless_lifetimes,
    clippy::just_underscores_and_digits, clippy::clone_on_copy, clippy::unit_arg)]
fn __action29<
    'err,
>(
    errors: &'err mut Vec<ErrorRecovery<usize, Tok, LexError>>,
    __0: (usize, Tok, usize),
    __1: (usize, usize, usize),
) -> Item
{
    let __start0 = __0.0.clone();
    let __end0 = __0.0.clone();
    let __temp0 = __action19(
        errors,
        &__start0,
        &__end0,
    );
    let __temp0 = (__start0, __temp0, __end0);
    __action9(
        errors,
        __temp0,
        __0,
        __1,
    )
}

#[allow(unused_variables)]
#[allow(clippy::too_many_arguments, clippy::needless_lifetimes,
    clippy::just_underscores_and_digits, clippy::clone_on_copy, clippy::unit_arg)]
fn __action30<
    'err,
>(
    errors: &'err mut Vec<ErrorRecovery<usize, Tok, LexError>>,
    __0: (usize, Tok, usize),
    __1: (usize, usize, usize),
) -> Item
{
    let __start0 = __0.0.clone();
    let __end0 = __0.0.clone();
    let __temp0 = __action19(
        errors,
        &__start0,
        &__end0,
    );
    let __temp0 = (__start0, __temp0, __end0);
    __action10(
        errors,
        __temp0,
        __0,
        __1,
    )
}

#[allow(unused_variables)]
#[allow(clippy::too_many_arguments, clippy::needless_lifetimes,
    clippy::just_underscores_and_digits, clippy::clone_on_copy, clippy::unit_arg)]
fn __action31<
    'err,
>(
    errors: &'err mut Vec<ErrorRecovery<usize, Tok, LexError>>,
    __0: (usize, Lit, usize),
    __1: (usize, usize, usize),
) -> Item
{
    let __start0 = __0.0.clone();
    let __end0 = __0.0.clone();
    let __temp0 = __action19(
        errors,
        &__start0,
        &__end0,
    );
    let __temp0 = (__start0, __temp0, __end0);
    __action11(
        errors,
        __temp0,
        __0,
        __1,
    )
}

#[allow(unused_variables)]
#[allow(clippy::too_many_arguments, clippy::needless_lifetimes,
    clippy::just_underscores_and_digits, clippy::clone_on_copy, clippy::unit_arg)]
fn __action32<
    'err,
>(
    errors: &'err mut Vec<ErrorRecovery<usize, Tok, LexError>>,
    __0: (usize, Tok, usize),
    __1: (usize, Val, usize),
    __2: (usize, usize, usize),
) -> Item
{
    let __start0 = __0.0.clone();
    let __end0 = __0.0.clone();
    let __temp0 = __action19(
        errors,
        &__start0,
        &__end0,
    );
    let __temp0 = (__start0, __temp0, __end0);
    __action12(
        errors,
        __temp0,
        __0,
        __1,
        __2,
    )
}

#[allow(unused_variables)]
#[allow(clippy::too_many_arguments, clippy::needless_lifetimes,
    clippy::just_underscores_and_digits, clippy::clone_on_copy, clippy::unit_arg)]
fn __action33<
    'err,
>(
    errors: &'err mut Vec<ErrorRecovery<usize, Tok, LexError>>,
    __0: (usize, Tok, usize),
    __1: (usize, Val, usize),
    __2: (usize, usize, usize),
) -> Item
{
    let __start0 = __0.0.clone();
    let __end0 = __0.0.clone();
    let __temp0 = __action19(
        errors,
        &__start0,
        &__end0,
    );
    let __temp0 = (__start0, __temp0, __end0);
    __action13(
        errors,
        __temp0,
        __0,
        __1,
        __2,
    )
}

#[allow(unused_variables)]
#[allow(clippy::too_many_arguments, clippy::needless_lifetimes,
    clippy::just_underscores_and_digits, clippy::clone_on_copy, clippy::unit_arg)]
fn __action34<
    'err,
>(
    errors: &'err mut Vec<ErrorRecovery<usize, Tok, LexError>>,
    __0: (usize, char, usize),
    __1: (usize, Val, usize),
    __2: (usize, usize, usize),
) -> Item
{
    let __start0 = __0.0.clone();
    let __end0 = __0.0.clone();
    let __temp0 = __action19(
        errors,
        &__start0,
        &__end0,
    );
    let __temp0 = (__start0, __temp0, __end0);
    __action14(
        errors,
        __temp0,
        __0,
        __1,
        __2,
    )
}

#[allow(unused_variables)]
#[allow(clippy::too_many_arguments, clippy::needless_lifetimes,
    clippy::just_underscores_and_digits, clippy::clone_on_copy, clippy::unit_arg)]
fn __action35<
    'err,
>(
    errors: &'err mut Vec<ErrorRecovery<usize, Tok, LexError>>,
    __0: (usize, Tok, usize),
    __1: (usize, Val, usize),
    __2: (usize, usize, usize),
) -> Item
{
    let __start0 = __0.0.clone();
    let __end0 = __0.0.clone();
    let __temp0 = __action19(
        errors,
        &__start0,
        &__end0,
    );
    let __temp0 = (__start0, __temp0, __end0);
    __action15(
        errors,
        __temp0,
        __0,
        __1,
        __2,
    )
}

#[allow(unused_variables)]
#[allow(clippy::too_many_arguments, clippy::needless_lifetimes,
    clippy::just_underscores_and_digits, clippy::clone_on_copy, clippy::unit_arg)]
fn __action36<
    'err,
>(
    errors: &'err mut Vec<ErrorRecovery<usize, Tok, LexError>>,
    __0: (usize, Tok, usize),
    __1: (usize, Lit, usize),
    __2: (usize, Tok, usize),
    __3: (usize, Lit, usize),
    __4: (usize, usize, usize),
) -> Item
{
    let __start0 = __0.0.clone();
    let __end0 = __0.0.clone();
    let __temp0 = __action19(
        errors,
        &__start0,
        &__end0,
    );
    let __temp0 = (__start0, __temp0, __end0);
    __action16(
        errors,
        __temp0,
        __0,
        __1,
        __2,
        __3,
        __4,
    )
}

#[allow(unused_variables)]
#[allow(clippy::too_many_arguments, clippy::needless_lifetimes,
    clippy::just_underscores_and_digits, clippy::clone_on_copy, clippy::unit_arg)]
fn __action37<
    'err,
>(
    errors: &'err mut Vec<ErrorRecovery<usize, Tok, LexError>>,
    __0: (usize, __lalrpop_util::ErrorRecovery<usize, Tok, LexError>, usize),
    __1: (usize, usize, usize),
) -> Item
{
    let __start0 = __0.0.clone();
    let __end0 = __0.0.clone();
    let __temp0 = __action19(
        errors,
        &__start0,
        &__end0,
    );
    let __temp0 = (__start0, __temp0, __end0);
    __action17(
        errors,
        __temp0,
        __0,
        __1,
    )
}

#[allow(unused_variables)]
#[allow(clippy::too_many_arguments, clippy::needless_lifetimes,
    clippy::just_underscores_and_digits, clippy::clone_on_copy, clippy::unit_arg)]
fn __action38<
    'err,
>(
    errors: &'err mut Vec<ErrorRecovery<usize, Tok, LexError>>,
    __0: (usize, Tok, usize),
) -> Item
{
    let __start0 = __0.2.clone();
    let __end0 = __0.2.clone();
    let __temp0 = __action18(
        errors,
        &__start0,
        &__end0,
    );
    let __temp0 = (__start0, __temp0, __end0);
    __action24(
        errors,
        __0,
        __temp0,
    )
}

#[allow(unused_variables)]
#[allow(clippy::too_many_arguments, clippy::needless_lifetimes,
    clippy::just_underscores_and_digits, clippy::clone_on_copy, clippy::unit_arg)]
fn __action39<
    'err,
>(
    errors: &'err mut Vec<ErrorRecovery<usize, Tok, LexError>>,
    __0: (usize, Tok, usize),
) -> Item
{
    let __start0 = __0.2.clone();
    let __end0 = __0.2.clone();
    let __temp0 = __action18(
        errors,
        &__start0,
        &__end0,
    );
    let __temp0 = (__start0, __temp0, __end0);
    __action25(
        errors,
        __0,
        __temp0,
    )
}

#[allow(unused_variables)]
#[allow(clippy::too_many_arguments, clippy::needless_lifetimes,
    clippy::just_underscores_and_digits, clippy::clone_on_copy, clippy::unit_arg)]
fn __action40<
    'err,
>(
    errors: &'err mut Vec<ErrorRecovery<usize, Tok, LexError>>,
    __0: (usize, Tok, usize),
) -> Item
{
    let __start0 = __0.2.clone();
    let __end0 = __0.2.clone();
    let __temp0 = __action18(
        errors,
        &__start0,
        &__end0,
    );
    let __temp0 = (__start0, __temp0, __end0);
    __action26(
        errors,
        __0,
        __temp0,
    )
}

#[allow(unused_variables)]
#[allow(clippy::too_many_arguments, clippy::needless_lifetimes,
    clippy::just_underscores_and_digits, clippy::clone_on_copy, clippy::unit_arg)]
fn __action41<
    'err,
>(
    errors: &'err mut Vec<ErrorRecovery<usize, Tok, LexError>>,
    __0: (usize, Tok, usize),
) -> Item
{
    let __start0 = __0.2.clone();
    let __end0 = __0.2.clone();
    let __temp0 = __action18(
        errors,
        &__start0,
        &__end0,
    );
    let __temp0 = (__start0, __temp0, __end0);
    __action27(
        errors,
        __0,
        __temp0,
    )
}

#[allow(unused_variables)]
#[allow(clippy::too_many_arguments, clippy::needless_lifetimes,
    clippy::just_underscores_and_digits, clippy::clone_on_copy, clippy::unit_arg)]
fn __action42<
    'err,
>(
    errors: &'err mut Vec<ErrorRecovery<usize, Tok, LexError>>,
    __0: (usize, Tok, usize),
) -> Item
{
    let __start0 = __0.2.clone();
    let __end0 = __0.2.clone();
    let __temp0 = __action18(
        errors,
        &__start0,
        &__end0,
    );
    let __temp0 = (__start0, __temp0, __end0);
    __action28(
        errors,
        __0,
        __temp0,
    )
}

#[allow(unused_variables)]
#[allow(clippy::too_many_arguments, clippy::needless_lifetimes,
    clippy::just_underscores_and_digits, clippy::clone_on_copy, clippy::unit_arg)]
fn __action43<
    'err,
>(
    errors: &'err mut Vec<ErrorRecovery<usize, Tok, LexError>>,
    __0: (usize, Tok, usize),
) -> Item
{
    let __start0 = __0.2.clone();
    let __end0 = __0.2.clone();
    let __temp0 = __action18(
        errors,
        &__start0,
        &__end0,
    );
    let __temp0 = (__start0, __temp0, __end0);
    __action29(
        errors,
        __0,
        __temp0,
    )
}

#[allow(unused_variables)]
#[allow(clippy::too_many_arguments, clippy::needless_lifetimes,
    clippy::just_underscores_and_digits, clippy::clone_on_copy, clippy::unit_arg)]
fn __action44<
    'err,
>(
    errors: &'err mut Vec<ErrorRecovery<usize, Tok, LexError>>,
    __0: (usize, Tok, usize),
) -> Item
{
    let __start0 = __0.2.clone();
    let __end0 = __0.2.clone();
    let __temp0 = __action18(
        errors,
        &__start0,
        &__end0,
    );
    let __temp0 = (__start0, __temp0, __end0);
    __action30(
        errors,
        __0,
        __temp0,
    )
}

#[allow(unused_variables)]
#[allow(clippy::too_many_arguments, clippy::needless_lifetimes,
    clippy::just_underscores_and_digits, clippy::clone_on_copy, clippy::unit_arg)]
fn __action45<
    'err,
>(
    errors: &'err mut Vec<ErrorRecovery<usize, Tok, LexError>>,
    __0: (usize, Lit, usize),
) -> Item
{
    let __start0 = __0.2.clone();
    let __end0 = __0.2.clone();
    let __temp0 = __action18(
        errors,
        &__start0,
        &__end0,
    );
    let __temp0 = (__start0, __temp0, __end0);
    __action31(
        errors,
        __0,
        __temp0,
    )
}

#[allow(unused_variables)]
#[allow(clippy::too_many_arguments, clippy::needless_lifetimes,
    clippy::just_underscores_and_digits, clippy::clone_on_copy, clippy::unit_arg)]
fn __action46<
    'err,
>(
    errors: &'err mut Vec<ErrorRecovery<usize, Tok, LexError>>,
    __0: (usize, Tok, usize),
    __1: (usize, Val, usize),
) -> Item
{
    let __start0 = __1.2.clone();
    let __end0 = __1.2.clone();
    let __temp0 = __action18(
        errors,
        &__start0,
        &__end0,
    );
    let __temp0 = (__start0, __temp0, __end0);
    __action32(
        errors,
        __0,
        __1,
        __temp0,
    )
}

#[allow(unused_variables)]
#[allow(clippy::too_many_arguments, clippy::needless_lifetimes,
    clippy::just_underscores_and_digits, clippy::clone_on_copy, clippy::unit_arg)]
fn __action47<
    'err,
>(
    errors: &'err mut Vec<ErrorRecovery<usize, Tok, LexError>>,
    __0: (usize, Tok, usize),
    __1: (usize, Val, usize),
) -> Item
{
    let __start0 = __1.2.clone();
    let __end0 = __1.2.clone();
    let __temp0 = __action18(
        errors,
        &__start0,
        &__end0,
    );
    let __temp0 = (__start0, __temp0, __end0);
    __action33(
        errors,
        __0,
        __1,
        __temp0,
    )
}

#[allow(unused_variables)]
#[allow(clippy::too_many_arguments, clippy::needless_lifetimes,
    clippy::just_underscores_and_digits, clippy::clone_on_copy, clippy::unit_arg)]
fn __action48<
    'err,
>(
    errors: &'err mut Vec<ErrorRecovery<usize, Tok, LexError>>,
    __0: (usize, char, usize),
    __1: (usize, Val, usize),
) -> Item
{
    let __start0 = __1.2.clone();
    let __end0 = __1.2.clone();
    let __temp0 = __action18(
        errors,
        &__start0,
        &__end0,
    );
    let __temp0 = (__start0, __temp0, __end0);
    __action34(
        errors,
        __0,
        __1,
        __temp0,
    )
}

#[allow(unused_variables)]
#[allow(clippy::too_many_arguments, clippy::needless_lifetimes,
    clippy::just_underscores_and_digits, clippy::clone_on_copy, clippy::unit_arg)]
fn __action49<
    'err,
>(
    errors: &'err mut Vec<ErrorRecovery<usize, Tok, LexError>>,
    __0: (usize, Tok, usize),
    __1: (usize, Val, usize),
) -> Item
{
    let __start0 = __1.2.clone();
    let __end0 = __1.2.clone();
    let __temp0 = __action18(
        errors,
        &__start0,
        &__end0,
    );
    let __temp0 = (__start0, __temp0, __end0);
    __action35(
        errors,
        __0,
        __1,
        __temp0,
    )
}

#[allow(unused_variables)]
#[allow(clippy::too_many_arguments, clippy::needless_lifetimes,
    clippy::just_underscores_and_digits, clippy::clone_on_copy, clippy::unit_arg)]
fn __action50<
    'err,
>(
    errors: &'err mut Vec<ErrorRecovery<usize, Tok, LexError>>,
    __0: (usize, Tok, usize),
    __1: (usize, Lit, usize),
    __2: (usize, Tok, usize),
    __3: (usize, Lit, usize),
) -> Item
{
    let __start0 = __3.2.clone();
    let __end0 = __3.2.clone();
    let __temp0 = __action18(
        errors,
        &__start0,
        &__end0,
    );
    let __temp0 = (__start0, __temp0, __end0);
    __action36(
        errors,
        __0,
        __1,
        __2,
        __3,
        __temp0,
    )
}

#[allow(unused_variables)]
#[allow(clippy::too_many_arguments, clippy::needless_lifetimes,
    clippy::just_underscores_and_digits, clippy::clone_on_copy, clippy::unit_arg)]
fn __action51<
    'err,
>(
    errors: &'err mut Vec<ErrorRecovery<usize, Tok, LexError>>,
    __0: (usize, __lalrpop_util::ErrorRecovery<usize, Tok, LexError>, usize),
) -> Item
{
    let __start0 = __0.2.clone();
    let __end0 = __0.2.clone();
    let __temp0 = __action18(
        errors,
        &__start0,
        &__end0,
    );
    let __temp0 = (__start0, __temp0, __end0);
    __action37(
        errors,
        __0,
        __temp0,
    )
}

#[allow(unused_variables)]
#[allow(clippy::too_many_arguments, clippy::needless_lifetimes,
    clippy::just_underscores_and_digits, clippy::clone_on_copy, clippy::unit_arg)]
fn __action52<
    'err,
>(
    errors: &'err mut Vec<ErrorRecovery<usize, Tok, LexError>>,
    __lookbehind: &usize,
    __lookahead: &usize,
) -> Vec<Item>
{
    let __start0 = __lookbehind.clone();
    let __end0 = __lookahead.clone();
    let __temp0 = __action20(
        errors,
        &__start0,
        &__end0,
    );
    let __temp0 = (__start0, __temp0, __end0);
    __action1(
        errors,
        __temp0,
    )
}

#[allow(unused_variables)]
#[allow(clippy::too_many_arguments, clippy::needless_lifetimes,
    clippy::just_underscores_and_digits, clippy::clone_on_copy, clippy::unit_arg)]
fn __action53<
    'err,
>(
    errors: &'err mut Vec<ErrorRecovery<usize, Tok, LexError>>,
    __0: (usize, alloc::vec::Vec<Item>, usize),
) -> Vec<Item>
{
    let __start0 = __0.0.clone();
    let __end0 = __0.2.clone();
    let __temp0 = __action21(
        errors,
        __0,
    );
    let __temp0 = (__start0, __temp0, __end0);
    __action1(
        errors,
        __temp0,
    )
}

#[allow(clippy::type_complexity, dead_code)]
pub trait __ToTriple<'err, >
{
    fn to_triple(self) -> Result<(usize,Tok,usize), __lalrpop_util::ParseError<usize, Tok, LexError>>;
}

impl<'err, > __ToTriple<'err, > for (usize, Tok, usize)
{
    fn to_triple(self) -> Result<(usize,Tok,usize), __lalrpop_util::ParseError<usize, Tok, LexError>> {
        Ok(self)
    }
}
impl<'err, > __ToTriple<'err, > for Result<(usize, Tok, usize), LexError>
{
    fn to_triple(self) -> Result<(usize,Tok,usize), __lalrpop_util::ParseError<usize, Tok, LexError>> {
        self.map_err(|error| __lalrpop_util::ParseError::User { error })
    }
}
