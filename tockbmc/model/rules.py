"""The RoboTool rules that tockbmc's model errors enforce, each cited by the error it explains.

An error on a model that parses cites, as `Diagnostic.rule`, the rule of RoboTool
(robochart-textual) that refuses the same model: a well-formedness condition of the RoboChart
reference manual as RoboChartValidator.xtend names it in a comment (`T1`, `Cn8`), else the issue
code that validator gives (`VarInitType`), else the part of Xtext that refuses it (`linking`,
`NamesAreUnique`).  Printed as `… [RoboTool rule T1]`; docs/language.md §5.1 lists every error
with its rule, and tests/test_rules.py keeps that table and this one in step.

An error that cites none of these is one of tockbmc's own bounds (`LIMIT`): RoboTool has no such
rule, and tockbmc refuses the input to keep itself within memory and time.
"""

from __future__ import annotations

VALIDATOR = "RoboChartValidator.xtend"

# Xtext refuses a name no declaration in scope answers to ("Couldn't resolve reference to …"),
# with the scope RoboChartScopeProvider.xtend computes.
LINKING = "linking"
# Xtext's NamesAreUniqueValidator, the composedCheck of robochart-textual's GenerateRoboChart.mwe2:
# two named elements of one file with one qualified name ("Duplicate … '…'").
UNIQUE = "NamesAreUnique"
# RoboCalcTypeProvider.typeFor gives an ill-typed expression no type, which the validator's check
# of the element around it then refuses (VarInitType, TransitionConditionTypeError, …).
TYPING = "typing"
# RoboChart.xtext itself: RoboTool cannot read the text.
GRAMMAR = "grammar"
# Not RoboTool's: one of tockbmc's bounds on nesting, chains of declarations and number length.
LIMIT = "tockbmc limit"

RULES: dict[str, str] = {
    LINKING: "Xtext linking under RoboChartScopeProvider: every name resolves to a declaration in scope",
    UNIQUE: "Xtext NamesAreUniqueValidator: one qualified name per named element of a file",
    TYPING: "RoboCalcTypeProvider.typeFor: an ill-typed expression has no type, refused by the check around it",
    GRAMMAR: "RoboChart.xtext: the text is not RoboChart",
    LIMIT: "none: tockbmc's bound on nesting, declaration chains or number length",
    "S2": "a state has at most one entry, during and exit action (stateWFC)",
    "IJ1": "no transition targets an initial junction (initialWFC)",
    "IJ2": "an initial junction has exactly one outgoing transition (initialWFC)",
    "FS1": "no transition starts in a final state (finalWFC)",
    "J3": "a transition with a trigger starts on a state (transitionWFC)",
    "T1": "a transition's source and target belong to its container (transitionWFC)",
    "PJ1": "a transition from a probabilistic junction has a probability (transitionWFC)",
    "PJ2": "a transition from a probabilistic junction has no condition (transitionWFC)",
    "PT1": "a transition with a probability starts from a probabilistic junction (transitionWFC)",
    "PT2": "a probability literal lies from 0 to 1 (transitionWFC)",
    "STM3": "a state machine has exactly one initial junction (checkStateMachineHasInitialState)",
    "M1": "a module has exactly one robotic platform (moduleWFC)",
    "Cn8": "the end of a unidirectional connection is not an output of its machine or its operations "
           "(checkControllerConnections)",
    "Cn9": "the start of a unidirectional connection is not an input of its machine or its operations "
           "(checkControllerConnections)",
    "Tg2": "a simple communication refers to an untyped event (communicationWellTyped)",
    "Tg5": "an input, output or sync communication refers to a typed event (communicationWellTyped)",
    "VarInitType": "a variable's initial value has its type (variableInitWellTyped)",
    "AssignmentTypeError": "an assignment's value has the type of its target (assignmentWellTyped)",
    "assignmentToParameter": "an operation's parameter is not assigned (checkAssignmentToParameter)",
    "TransitionConditionTypeError": "a transition's condition is boolean (transitionWellTyped)",
    "IfStmtTypeError": "an if statement's condition is boolean (ifStmtWellTyped)",
    "WaitTypeError": "a wait's duration is an integer or a set of integers (waitWellTyped)",
    "InputCommunicationTypeError": "an input's variable has its event's type (communicationWellTyped)",
    "OutputCommunicationTypeError": "an output's value has its event's type (communicationWellTyped)",
    "FieldDefinitionTypeError": "a record literal's field has the field's type (wfc_RecordFieldDefinition)",
    "IncorrectNumberOfArguments": "a call gives a function or parameterised literal as many arguments as it "
                                  "takes (functionCallWellTyped, constantWellTyped, constantConstructionWellTyped)",
    "UndefinedTypeInArguments": "a function's argument has its parameter's type (functionCallWellTyped)",
    "TupleIndexOutOfBounds": "a tuple is indexed by a numeral from 1 to its size (tupleHasNatIndex)",
    "RPConnectionIncompatibleType": "the events a connection joins have one type, or none (rpConnectionAsync)",
}


def cite(rule: str) -> str:
    """The suffix an error's message is printed with: ` [RoboTool rule T1]`."""
    return f" [RoboTool rule {rule}]" if rule else ""
