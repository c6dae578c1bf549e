// The GeoScenario behavior-tree language (`.btree`, SPEC §8), as the reference implementation
// reads it: an indentation-based tree of composites and leaves.
//
//   behaviortree drive:
//       ?
//           ->
//               condition c_occ(lane_occupied(zid=FRONT, distance=30))
//               maneuver m_follow(MFollowConfig())
//           maneuver m_keep(MVelKeepConfig(vel=MP(14.0,10,6)))
//
// A call is preferred over a name followed by a tuple (`MP(1,2,3)` is one value, since items may
// be separated by spaces). INDENT and DEDENT are not produced by this lexer: compiler/gss/btree.cpp turns the NL tokens
// (which carry the next line's indentation) into them. Arguments inside a call may be separated
// by commas or, as the reference tolerates, by spaces only.
grammar Btree;

tokens { INDENT, DEDENT }

btreeFile : NL* treeDecl+ EOF ;
treeDecl  : BEHAVIORTREE NAME ':' NL INDENT node DEDENT ;
node      : composite | leaf ;
composite : op=(FALLBACK | SEQUENCE | PARALLEL) NL INDENT node+ DEDENT ;
leaf      : (condition | maneuver | subtree) NL ;
condition : CONDITION NAME '(' call ')' ;
maneuver  : MANEUVER NAME '(' call ')' ;
subtree   : SUBTREE NAME '(' (item (','? item)*)? ')' ;
call      : NAME '(' (item (','? item)*)? ')' ;
item      : (NAME '=')? value ;
value
    : call                                    # callValue
    | NUMBER                                  # numberValue
    | NAME                                    # nameValue
    | '(' value (',' value)* ')'              # tupleValue
    ;

BEHAVIORTREE : 'behaviortree' ;
CONDITION    : 'condition' ;
MANEUVER     : 'maneuver' ;
SUBTREE      : 'subtree' ;
FALLBACK     : '?' ;
SEQUENCE     : '->' ;
PARALLEL     : '||' ;
NUMBER       : [+-]? ([0-9]+ ('.' [0-9]*)? | '.' [0-9]+) ([eE] [+-]? [0-9]+)? ;
NAME         : [a-zA-Z_] [a-zA-Z_0-9]* ;
NL           : '\r'? '\n' [ \t]* ;
WS           : [ \t]+ -> skip ;
COMMENT      : '#' ~[\r\n]* -> skip ;
ANY          : . ;
